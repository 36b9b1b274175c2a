// Single-key shortcuts (1–4, B, M, L, Space, E, F...) act on the canvas wherever the focus is,
// except in a widget where the user is typing (a line edit, a spin box being edited, an editable
// combo box). Escape returns the focus to the canvas. Spin boxes and combo boxes take the focus
// by Tab or click (never by the wheel) and hand it back to the canvas once a value is entered or
// an item picked, so a later key is a shortcut again.
#pragma once

#include <QList>
#include <QObject>
#include <QPointer>

class QAction;
class QWidget;

namespace glint::studio {

class CanvasKeys : public QObject {
    Q_OBJECT
  public:
    /// Routes the single-key `actions` of `window` to the canvas; installs itself on qApp.
    CanvasKeys(QWidget* window, QWidget* canvas, const QList<QAction*>& actions);
    ~CanvasKeys() override;

  protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    void adopt(QWidget* widget);
    bool isSingleKey(int key, Qt::KeyboardModifiers modifiers) const;

    QPointer<QWidget> m_window;
    QPointer<QWidget> m_canvas;
    QList<QAction*> m_actions;
};

}  // namespace glint::studio
