#include "model/look_command.h"

#include <QJsonArray>

#include "glint/image/error.h"

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
    setText(QObject::tr("Change %1 %2")
                .arg(QString::fromStdString(m_item), QString::fromStdString(m_property)));
}

void LookCommand::apply(const std::array<double, 3>& value, const char* op) {
    m_document->setLook(m_item, m_property, value, m_render);
    JournalEntry entry;
    if (std::string_view(op) == "look") {
        entry.op = {{QStringLiteral("op"), QStringLiteral("look")},
                    {QStringLiteral("item"), QString::fromStdString(m_item)},
                    {QStringLiteral("property"), QString::fromStdString(m_property)},
                    {QStringLiteral("before"), QJsonArray{m_before[0], m_before[1], m_before[2]}},
                    {QStringLiteral("after"), QJsonArray{m_after[0], m_after[1], m_after[2]}}};
    } else {
        entry.op = {{QStringLiteral("op"), QString::fromLatin1(op)}};
    }
    m_session->record(entry);
}

void LookCommand::undo() {
    apply(m_before, "undo");
}

void LookCommand::redo() {
    apply(m_after, m_first ? "look" : "redo");
    m_first = false;
}

}  // namespace glint::studio
