// How the side panels sit in the window so that it fits a 1366×768 laptop: each panel scrolls
// vertically inside its dock instead of making the window taller, and keeps its own width.
#pragma once

#include <QScrollArea>

class QDockWidget;
class QMainWindow;

namespace glint::studio {

/// A scroll area that scrolls vertically only: as wide as its panel needs, as short as asked.
class VerticalScrollArea : public QScrollArea {
    Q_OBJECT
  public:
    explicit VerticalScrollArea(QWidget* panel, QWidget* parent = nullptr);
    QSize minimumSizeHint() const override;
    QSize sizeHint() const override;
};

/// A dock of `content` (named `name` for the saved window state) that moves and floats.
QDockWidget* makeDock(QMainWindow* window, const QString& title, const QString& name,
                      QWidget* content);

}  // namespace glint::studio
