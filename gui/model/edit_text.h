// The undo stack's name of each edit (Edit ▸ Undo "Stroke on layer 2"), from the operation the
// autosave journal records: the same names for the studio's own edits and for the history a
// restore gives back (model/recovery.h).
#pragma once

#include <QString>

#include <string>

#include "model/journal_codec.h"

namespace glint::studio {

/// The name of a session edit (an undoable operation: neither Start, Input, Clear, Undo nor Redo,
/// which name none and give "").
QString editText(const journal_codec::Op& op);
/// The name of a look edit of `item`'s `property`.
QString lookEditText(const std::string& item, const std::string& property);

}  // namespace glint::studio
