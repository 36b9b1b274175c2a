#include "model/look_command.h"

#include <QJsonArray>

#include "glint/image/error.h"
#include "model/edit_text.h"

namespace glint::studio {

LookCommand::LookCommand(Document* document, SessionAdapter* session, std::string item,
                         std::string property, std::array<double, 3> before,
                         std::array<double, 3> after, bool render)
    : m_document(document),
      m_session(session),
      m_item(std::move(item)),
      m_property(std::move(property)),
      m_before(before),
      m_after(after),
      m_render(render) {
    setText(lookEditText(m_item, m_property));
}

void LookCommand::apply(const std::array<double, 3>& value, const char* op) {
    m_document->setLook(m_item, m_property, value, m_render);
    JournalEntry entry;
    if (std::string_view(op) == "look") {
        entry.op = journalOp(m_item, m_property, m_before, m_after);
    } else {
        entry.op = {{QStringLiteral("op"), QString::fromLatin1(op)}};
    }
    m_session->record(entry);
}

QJsonObject LookCommand::journalOp(const std::string& item, const std::string& property,
                                   const std::array<double, 3>& before,
                                   const std::array<double, 3>& after) {
    return {{QStringLiteral("op"), QStringLiteral("look")},
            {QStringLiteral("item"), QString::fromStdString(item)},
            {QStringLiteral("property"), QString::fromStdString(property)},
            {QStringLiteral("before"), QJsonArray{before[0], before[1], before[2]}},
            {QStringLiteral("after"), QJsonArray{after[0], after[1], after[2]}}};
}

void LookCommand::undo() {
    if (m_session->restoringHistory()) return;  // a restore's history: the look is as it was
    apply(m_before, "undo");
}

void LookCommand::redo() {
    if (!m_session->restoringHistory()) apply(m_after, m_first ? "look" : "redo");
    m_first = false;
}

}  // namespace glint::studio
