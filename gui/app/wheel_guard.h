// The mouse wheel scrolls panels, not the values under it: over a combo box, spin box or slider
// that does not have the keyboard focus, the wheel scrolls the panel around it (or does nothing
// where there is none) instead of changing the value. A control the user clicked into (it has
// the focus) takes the wheel as usual.
#pragma once

#include <QObject>

class QWidget;

namespace glint::studio {

/// An application-wide event filter; installed by the main window, gone with it.
class WheelGuard : public QObject {
    Q_OBJECT
  public:
    /// Installs itself on the application, a child of `owner`.
    explicit WheelGuard(QObject* owner);
    ~WheelGuard() override;

    /// The value control `widget` is part of (itself, or the spin box its line edit belongs
    /// to) when it is a combo box, spin box or slider (not a scroll bar); null otherwise.
    static QWidget* valueControl(QWidget* widget);

  protected:
    bool eventFilter(QObject* watched, QEvent* event) override;
};

}  // namespace glint::studio
