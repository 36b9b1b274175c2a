#include "views/text_editing.h"

#include <QAbstractSpinBox>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QTextEdit>

namespace glint::studio {

namespace {

// The spin box `widget` belongs to (its line edit is the focus widget).
QAbstractSpinBox* enclosingSpinBox(const QWidget* widget) {
    for (QWidget* w = const_cast<QWidget*>(widget); w; w = w->parentWidget())
        if (auto* spin = qobject_cast<QAbstractSpinBox*>(w)) return spin;
    return nullptr;
}

}  // namespace

bool isTextEditing(const QWidget* widget) {
    if (!widget) return false;
    if (auto* line = qobject_cast<const QLineEdit*>(widget); line && !line->isReadOnly())
        return true;
    if (auto* text = qobject_cast<const QTextEdit*>(widget); text && !text->isReadOnly())
        return true;
    if (auto* plain = qobject_cast<const QPlainTextEdit*>(widget); plain && !plain->isReadOnly())
        return true;
    if (auto* spin = enclosingSpinBox(widget); spin && !spin->isReadOnly()) return true;
    return false;
}

}  // namespace glint::studio
