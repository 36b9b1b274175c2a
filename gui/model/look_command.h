// A look edit (one material, light or environment property) as an undo step: redo sets the new
// value, undo the old one, each re-rendering; both are reported to the autosave journal.
#pragma once

#include <QJsonObject>
#include <QUndoCommand>

#include <array>
#include <string>

#include "model/document.h"
#include "model/session_adapter.h"

namespace glint::studio {

class LookCommand : public QUndoCommand {
  public:
    /// `render` false applies the value without rendering (restoring an autosave).
    LookCommand(Document* document, SessionAdapter* session, std::string item, std::string property,
                std::array<double, 3> before, std::array<double, 3> after, bool render = true);
    void undo() override;
    void redo() override;

  private:
    /// The journal's JSON of a look edit ("op": "look").
    static QJsonObject journalOp(const std::string& item, const std::string& property,
                                 const std::array<double, 3>& before,
                                 const std::array<double, 3>& after);
    void apply(const std::array<double, 3>& value, const char* op);

    Document* m_document;
    SessionAdapter* m_session;
    std::string m_item, m_property;
    std::array<double, 3> m_before, m_after;
    bool m_render;
    bool m_first = true;
};

}  // namespace glint::studio
