// The shortcut overlay (F1): a translucent sheet over the window listing every action that has
// a shortcut, generated from the actions themselves so it never goes stale.
#pragma once

#include <QList>
#include <QWidget>

class QAction;

namespace glint::studio {

class HelpOverlay : public QWidget {
    Q_OBJECT
  public:
    explicit HelpOverlay(QWidget* parent);
    /// The actions to list (those with a shortcut), in order.
    void setActions(const QList<QAction*>& actions);
    /// Shows the overlay over the whole parent, or hides it.
    void toggle();

  protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    QList<QAction*> m_actions;
};

}  // namespace glint::studio
