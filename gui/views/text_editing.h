// Whether the user is typing into a widget (a line edit, a text edit, a spin box): keys go to it,
// not to the window's single-key shortcuts, and a click into the canvas only takes them back.
#pragma once

class QWidget;

namespace glint::studio {

/// True when `widget` takes typed text: keys go to it, not to shortcuts.
bool isTextEditing(const QWidget* widget);

}  // namespace glint::studio
