#include "app/panel_layout.h"

#include <QDockWidget>
#include <QGuiApplication>
#include <QMainWindow>
#include <QScreen>
#include <QScrollBar>
#include <QStyle>
#include <QTimer>

#include <algorithm>

namespace glint::studio {

namespace {
constexpr int kMinPanelHeight = 120;   // a few rows of any panel stay visible
constexpr int kPreferredHeight = 360;  // what a panel asks for when it could use more
// The window manager's title bar and borders, not known before the window is shown.
constexpr int kFrameWidth = 16, kFrameHeight = 40;
}  // namespace

VerticalScrollArea::VerticalScrollArea(QWidget* panel, QWidget* parent) : QScrollArea(parent) {
    setWidgetResizable(true);
    setFrameShape(QFrame::NoFrame);
    setHorizontalScrollBarPolicy(Qt::ScrollBarAsNeeded);
    setVerticalScrollBarPolicy(Qt::ScrollBarAsNeeded);
    setWidget(panel);
}

QSize VerticalScrollArea::minimumSizeHint() const {
    // The panel's width and room for the scroll bar, up to kPanelMinWidth; any height.
    const int bar = style()->pixelMetric(QStyle::PM_ScrollBarExtent, nullptr, this);
    const int panelWidth = widget() ? widget()->minimumSizeHint().width() : 0;
    return {std::min(panelWidth + bar + 2 * frameWidth(), kPanelMinWidth), kMinPanelHeight};
}

QSize VerticalScrollArea::sizeHint() const {
    const int bar = style()->pixelMetric(QStyle::PM_ScrollBarExtent, nullptr, this);
    const QSize panel = widget() ? widget()->sizeHint() : QSize();
    // Not taller than a share of a laptop screen: a dock below or above keeps room.
    return {panel.width() + bar + 2 * frameWidth(),
            std::min(panel.height(), kPreferredHeight) + 2 * frameWidth()};
}

QDockWidget* makeDock(QMainWindow* window, const QString& title, const QString& name,
                      QWidget* content) {
    auto* d = new QDockWidget(title, window);
    d->setObjectName(name);
    d->setWidget(content);
    // Closable: View > the panel's name brings it back.
    d->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable |
                   QDockWidget::DockWidgetClosable);
    return d;
}

namespace {

class PanelWidener : public QObject {
  public:
    PanelWidener(QMainWindow* window, const QList<QDockWidget*>& docks)
        : QObject(window), m_window(window), m_docks(docks) {
        window->installEventFilter(this);
    }

  protected:
    bool eventFilter(QObject* watched, QEvent* event) override {
        // After the layout settled at the new size.
        if (watched == m_window && event->type() == QEvent::Resize)
            QTimer::singleShot(0, this, &PanelWidener::widen);
        return false;
    }

  private:
    void widen() {
        const QWidget* central = m_window->centralWidget();
        if (!central) return;
        int spare = central->width() - central->minimumSizeHint().width();
        QList<QDockWidget*> docks;
        QList<int> widths;
        for (QDockWidget* dock : m_docks) {
            if (!dock->isVisible() || dock->isFloating() || !dock->widget()) continue;
            const int wanted = dock->widget()->sizeHint().width() - dock->widget()->width();
            const int grow = std::min(wanted, spare);
            if (grow <= 0) continue;
            docks << dock;
            widths << dock->width() + grow;
            spare -= grow;
        }
        if (!docks.isEmpty()) m_window->resizeDocks(docks, widths, Qt::Horizontal);
    }

    QMainWindow* m_window;
    QList<QDockWidget*> m_docks;
};

}  // namespace

void keepPanelsWide(QMainWindow* window, const QList<QDockWidget*>& docks) {
    new PanelWidener(window, docks);
}

QRect windowPlacement(const QRect& available, QSize preferred, QSize minimum) {
    const QSize frame(kFrameWidth, kFrameHeight);
    const QSize size = (preferred + frame).boundedTo(available.size()).expandedTo(minimum + frame);
    return {available.x() + std::max(0, (available.width() - size.width()) / 2),
            available.y() + std::max(0, (available.height() - size.height()) / 2), size.width(),
            size.height()};
}

void placeOnScreen(QWidget& window, QSize preferred, bool keepInside) {
    const QScreen* screen = window.screen() ? window.screen() : QGuiApplication::primaryScreen();
    if (!screen) {
        window.resize(preferred);
        return;
    }
    const QRect available = screen->availableGeometry();
    if (keepInside &&
        available.contains(window.geometry().adjusted(0, -kFrameHeight, kFrameWidth, 0)))
        return;
    const QRect frame = windowPlacement(available, preferred, window.minimumSizeHint());
    window.resize(frame.size() - QSize(kFrameWidth, kFrameHeight));
    window.move(frame.topLeft());  // move() places the frame's corner
}

}  // namespace glint::studio
