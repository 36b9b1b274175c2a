#include "app/panel_layout.h"

#include <QDockWidget>
#include <QMainWindow>
#include <QScrollBar>
#include <QStyle>

#include <algorithm>

namespace glint::studio {

namespace {
constexpr int kMinPanelHeight = 120;   // a few rows of any panel stay visible
constexpr int kPreferredHeight = 360;  // what a panel asks for when it could use more
}  // namespace

VerticalScrollArea::VerticalScrollArea(QWidget* panel, QWidget* parent) : QScrollArea(parent) {
    setWidgetResizable(true);
    setFrameShape(QFrame::NoFrame);
    setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    setVerticalScrollBarPolicy(Qt::ScrollBarAsNeeded);
    setWidget(panel);
}

QSize VerticalScrollArea::minimumSizeHint() const {
    // The panel's width and room for the scroll bar; any height.
    const int bar = style()->pixelMetric(QStyle::PM_ScrollBarExtent, nullptr, this);
    const int panelWidth = widget() ? widget()->minimumSizeHint().width() : 0;
    return {panelWidth + bar + 2 * frameWidth(), kMinPanelHeight};
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

}  // namespace glint::studio
