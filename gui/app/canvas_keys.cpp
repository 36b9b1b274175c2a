#include "app/canvas_keys.h"

#include <QAbstractSpinBox>
#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QKeyEvent>

#include "views/text_editing.h"

namespace glint::studio {

namespace {

constexpr char kAdopted[] = "glintCanvasKeys";

}  // namespace

CanvasKeys::CanvasKeys(QWidget* window, QWidget* canvas, const QList<QAction*>& actions)
    : QObject(window), m_window(window), m_canvas(canvas), m_actions(actions) {
    qApp->installEventFilter(this);
}

CanvasKeys::~CanvasKeys() {
    qApp->removeEventFilter(this);
}

bool CanvasKeys::isSingleKey(int key, Qt::KeyboardModifiers modifiers) const {
    // Shift is part of a single key (Shift+E); Ctrl, Alt and Meta make a command.
    if (modifiers & (Qt::ControlModifier | Qt::AltModifier | Qt::MetaModifier)) return false;
    const QKeySequence pressed(QKeyCombination(modifiers & Qt::ShiftModifier, Qt::Key(key)));
    for (const QAction* a : m_actions)
        for (const QKeySequence& s : a->shortcuts())
            if (s.count() == 1 && s.matches(pressed) == QKeySequence::ExactMatch) return true;
    return false;
}

void CanvasKeys::adopt(QWidget* widget) {
    // Spin boxes and combo boxes: focus by Tab or click (not by the wheel: scrolling the panel
    // must not take the keys from the canvas), and back to the canvas after use.
    const bool spin = qobject_cast<QAbstractSpinBox*>(widget) != nullptr;
    auto* combo = qobject_cast<QComboBox*>(widget);
    if ((!spin && !combo) || widget->property(kAdopted).toBool()) return;
    widget->setProperty(kAdopted, true);
    if (widget->focusPolicy() & Qt::TabFocus) widget->setFocusPolicy(Qt::StrongFocus);
    auto back = [this, widget] {
        // Only when the value was entered here (Enter, an item picked), not when the user
        // clicked elsewhere.
        if (m_canvas && widget->hasFocus()) m_canvas->setFocus(Qt::OtherFocusReason);
    };
    if (spin)
        connect(static_cast<QAbstractSpinBox*>(widget), &QAbstractSpinBox::editingFinished, this,
                back);
    else if (!combo->isEditable())
        connect(combo, &QComboBox::activated, this, back);
}

bool CanvasKeys::eventFilter(QObject* watched, QEvent* event) {
    // Every event of the application passes here: only two kinds are of interest.
    if (event->type() != QEvent::Polish && event->type() != QEvent::ShortcutOverride) return false;
    auto* widget = qobject_cast<QWidget*>(watched);
    if (!widget || !m_window || widget->window() != m_window) return false;
    if (event->type() == QEvent::Polish) {
        adopt(widget);
        return false;
    }
    if (event->type() != QEvent::ShortcutOverride) return false;
    auto* key = static_cast<QKeyEvent*>(event);
    if (key->key() == Qt::Key_Escape && m_canvas && widget != m_canvas) {
        // Escape leaves any field for the canvas (and still cancels a render).
        m_canvas->setFocus(Qt::ShortcutFocusReason);
        return false;
    }
    if (isTextEditing(widget) || !isSingleKey(key->key(), key->modifiers())) return false;
    // Not overridden: the window's shortcut runs instead of the widget's own use of the key
    // (Space opening a combo box, pressing a button).
    key->ignore();
    return true;
}

}  // namespace glint::studio
