// How the side panels sit in the window so that it fits a 1280×720 laptop: each panel scrolls
// vertically inside its dock instead of making the window taller, asks for at most
// kPanelMinWidth of the window's width (a narrower dock scrolls it sideways too, so that nothing
// is cut off), and the window opens inside the screen's available area.
#pragma once

#include <QList>
#include <QRect>
#include <QScrollArea>

class QDockWidget;
class QMainWindow;
class QWidget;

namespace glint::studio {

/// The most width a side panel asks of the window: the look, the comparison and the workflow
/// beside the viewer's least width fit 1280 px.
constexpr int kPanelMinWidth = 300;

/// A scroll area that scrolls vertically: as wide as its panel needs (up to kPanelMinWidth; a
/// wider panel scrolls sideways when the dock is narrower than it), as short as asked.
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

/// Widens `docks` towards their panels' preferred width whenever `window` is resized and its
/// central widget has width to spare (a window opened small and then enlarged: the main window
/// would give all the new width to the central widget and leave a panel scrolling sideways).
void keepPanelsWide(QMainWindow* window, const QList<QDockWidget*>& docks);

/// Where a window of `preferred` size (at least `minimum`) goes on a screen whose available area
/// (without task bars) is `available`: its frame (title bar and borders included), the preferred
/// size or what of it fits, centred.
QRect windowPlacement(const QRect& available, QSize preferred, QSize minimum);

/// Gives `window` the `preferred` size or what of it fits the available area of its screen (the
/// task bar and the title bar left out), at least its minimum size, and centres it there. A
/// window already inside the available area (a restored geometry) keeps its place when
/// `keepInside` is true.
void placeOnScreen(QWidget& window, QSize preferred, bool keepInside = false);

}  // namespace glint::studio
