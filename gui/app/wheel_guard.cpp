#include "app/wheel_guard.h"

#include <QAbstractScrollArea>
#include <QAbstractSpinBox>
#include <QApplication>
#include <QComboBox>
#include <QScrollBar>
#include <QSlider>
#include <QWheelEvent>

namespace glint::studio {

WheelGuard::WheelGuard(QObject* owner) : QObject(owner) {
    qApp->installEventFilter(this);
}

WheelGuard::~WheelGuard() {
    qApp->removeEventFilter(this);
}

QWidget* WheelGuard::valueControl(QWidget* widget) {
    auto isControl = [](QWidget* w) {
        return qobject_cast<QComboBox*>(w) || qobject_cast<QAbstractSpinBox*>(w) ||
               qobject_cast<QSlider*>(w);
    };
    if (isControl(widget)) return widget;
    // A spin box's or an editable combo box's line edit receives the wheel first.
    QWidget* parent = widget->parentWidget();
    return parent && isControl(parent) ? parent : nullptr;
}

bool WheelGuard::eventFilter(QObject* watched, QEvent* event) {
    if (event->type() != QEvent::Wheel || !watched->isWidgetType()) return false;
    QWidget* control = valueControl(static_cast<QWidget*>(watched));
    if (!control || control->hasFocus()) return false;
    // The panel around the control scrolls, as if the wheel were over its background.
    for (QWidget* p = control->parentWidget(); p; p = p->parentWidget())
        if (auto* area = qobject_cast<QAbstractScrollArea*>(p)) {
            auto* wheel = static_cast<QWheelEvent*>(event);
            QScrollBar* bar = area->verticalScrollBar();
            if (bar && bar->isVisible()) {
                QWheelEvent copy(bar->mapFromGlobal(wheel->globalPosition()),
                                 wheel->globalPosition(), wheel->pixelDelta(), wheel->angleDelta(),
                                 wheel->buttons(), wheel->modifiers(), wheel->phase(),
                                 wheel->inverted());
                QCoreApplication::sendEvent(bar, &copy);
            }
            break;
        }
    return true;  // the value stays
}

}  // namespace glint::studio
