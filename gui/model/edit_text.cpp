#include "model/edit_text.h"

#include <QObject>

#include <variant>

#include "model/layer_names.h"

namespace glint::studio {

QString editText(const journal_codec::Op& op) {
    namespace jc = journal_codec;
    auto tr = [](const char* text) { return QObject::tr(text); };
    if (const auto* add = std::get_if<jc::AddLayer>(&op))
        return tr("Add %1").arg(layerName(add->filter, add->params));
    if (std::holds_alternative<jc::AddLayers>(op)) return tr("Auto start");
    if (const auto* remove = std::get_if<jc::RemoveLayer>(&op))
        return tr("Remove layer %1").arg(remove->index + 1);
    if (const auto* rename = std::get_if<jc::RenameLayer>(&op))
        return tr("Rename layer %1").arg(rename->index + 1);
    if (const auto* weights = std::get_if<jc::Weights>(&op))
        return tr("Set the weights of layer %1").arg(weights->index + 1);
    if (const auto* fill = std::get_if<jc::Fill>(&op))
        return tr("Fill layer %1").arg(fill->index + 1);
    if (const auto* stroke = std::get_if<jc::Stroke>(&op))
        return tr("Stroke on layer %1").arg(stroke->layer + 1);
    if (std::holds_alternative<jc::Apply>(op)) return tr("Diffuse the weights");
    return {};
}

QString lookEditText(const std::string& item, const std::string& property) {
    return QObject::tr("Change %1 %2")
        .arg(QString::fromStdString(item), QString::fromStdString(property));
}

}  // namespace glint::studio
