#include "model/journal_codec.h"

#include <QJsonArray>
#include <QString>

#include <cmath>

#include "glint/image/error.h"
#include "model/session_state.h"

namespace glint::studio::journal_codec {

namespace {

// Numbers, and lists of strings (an external denoiser's command) as arrays.
QJsonObject paramsToJson(const denoise::ParamValues& params) {
    QJsonObject o;
    for (const auto& [name, value] : params) o.insert(QString::fromStdString(name), value);
    for (const auto& [name, list] : params.strings) {
        QJsonArray items;
        for (const std::string& item : list) items.append(QString::fromStdString(item));
        o.insert(QString::fromStdString(name), items);
    }
    return o;
}

denoise::ParamValues paramsFromJson(const QJsonValue& v) {
    const QJsonObject o = v.toObject();
    denoise::ParamValues params;
    for (auto it = o.begin(); it != o.end(); ++it) {
        const std::string name = it.key().toStdString();
        params[name] = it.value().toDouble();  // 0 for a list: its numeric slot
        if (!it.value().isArray()) continue;
        std::vector<std::string>& list = params.strings[name];
        for (const QJsonValue& item : it.value().toArray())
            list.push_back(item.toString().toStdString());
    }
    return params;
}

QString modeName(denoise::BrushMode mode) {
    return mode == denoise::BrushMode::Add ? QStringLiteral("add") : QStringLiteral("subtract");
}

denoise::BrushMode modeFromJson(const QJsonValue& v) {
    return v.toString() == QStringLiteral("subtract") ? denoise::BrushMode::Subtract
                                                      : denoise::BrushMode::Add;
}

QJsonObject layerToJson(const denoise::LayerSpec& spec) {
    return {{QStringLiteral("filter"), QString::fromStdString(spec.filter)},
            {QStringLiteral("params"), paramsToJson(spec.params)}};
}

QJsonArray indicesToJson(const std::vector<std::size_t>& indices) {
    QJsonArray a;
    for (std::size_t i : indices) a.append(qint64(i));
    return a;
}

std::vector<denoise::LayerSpec> layersFromJson(const QJsonValue& v) {
    std::vector<denoise::LayerSpec> layers;
    for (const QJsonValue& item : v.toArray()) {
        const QJsonObject l = item.toObject();
        layers.emplace_back(l.value(QStringLiteral("filter")).toString().toStdString(),
                            paramsFromJson(l.value(QStringLiteral("params"))));
    }
    return layers;
}

std::size_t index(const QJsonObject& o, const char* key) {
    return std::size_t(o.value(QLatin1String(key)).toInteger());
}

}  // namespace

std::vector<Image> correctionImages(const std::vector<denoise::LayerSpec>& layers) {
    std::vector<Image> images;
    for (const denoise::LayerSpec& spec : layers)
        if (spec.correction) {
            images.push_back(spec.correction->result);
            images.push_back(spec.correction->blend);
        }
    return images;
}

void takeCorrections(std::vector<denoise::LayerSpec>& layers, const std::vector<Image>& images) {
    std::size_t next = layers.size();
    for (denoise::LayerSpec& spec : layers) {
        if (spec.filter != denoise::kAutoCorrection) continue;
        if (next + 2 > images.size())
            throw Error(ErrorKind::Format,
                        "the journal entry lacks the images of auto's correction");
        spec.correction = std::make_shared<const denoise::SessionCorrection>(
            denoise::SessionCorrection{images[next], images[next + 1]});
        next += 2;
    }
}

namespace {

/// The JSON of one operation, by type.
struct Encoder {
    QJsonObject operator()(const Start& s) const {
        QJsonArray layers;
        for (const auto& spec : s.layers) layers.append(layerToJson(spec));
        QJsonArray names;
        for (const std::string& name : s.names) names.append(QString::fromStdString(name));
        return {{QStringLiteral("op"), QStringLiteral("start")},
                {QStringLiteral("names"), names},
                {QStringLiteral("options"),
                 QJsonObject{
                     {QStringLiteral("prefilter"), s.options.prefilter},
                     {QStringLiteral("prefilterParams"), paramsToJson(s.options.prefilterParams)}}},
                {QStringLiteral("layers"), layers},
                {QStringLiteral("bank"), QString::fromStdString(s.bankDir)}};
    }
    QJsonObject operator()(const Input&) const {
        return {{QStringLiteral("op"), QStringLiteral("input")}};
    }
    QJsonObject operator()(const AddLayer& a) const {
        return {{QStringLiteral("op"), QStringLiteral("addLayer")},
                {QStringLiteral("filter"), QString::fromStdString(a.filter)},
                {QStringLiteral("params"), paramsToJson(a.params)},
                {QStringLiteral("fill"), a.fill}};
    }
    QJsonObject operator()(const AddLayers& a) const {
        QJsonArray layers;
        for (const auto& spec : a.layers) layers.append(layerToJson(spec));
        return {{QStringLiteral("op"), QStringLiteral("addLayers")},
                {QStringLiteral("layers"), layers}};
    }
    QJsonObject operator()(const RemoveLayer& r) const {
        return {{QStringLiteral("op"), QStringLiteral("removeLayer")},
                {QStringLiteral("index"), qint64(r.index)}};
    }
    QJsonObject operator()(const RenameLayer& r) const {
        return {{QStringLiteral("op"), QStringLiteral("renameLayer")},
                {QStringLiteral("index"), qint64(r.index)},
                {QStringLiteral("name"), QString::fromStdString(r.name)}};
    }
    QJsonObject operator()(const Weights& w) const {
        return {{QStringLiteral("op"), QStringLiteral("weights")},
                {QStringLiteral("index"), qint64(w.index)}};
    }
    QJsonObject operator()(const Fill& f) const {
        return {{QStringLiteral("op"), QStringLiteral("fill")},
                {QStringLiteral("index"), qint64(f.index)},
                {QStringLiteral("mode"), modeName(f.mode)}};
    }
    QJsonObject operator()(const Stroke& s) const {
        QJsonArray dabs;
        for (double v : s.dabs) dabs.append(v);
        return {{QStringLiteral("op"), QStringLiteral("stroke")},
                {QStringLiteral("layer"), qint64(s.layer)},
                {QStringLiteral("size"), s.brush.size},
                {QStringLiteral("softness"), s.brush.softness},
                {QStringLiteral("mode"), modeName(s.mode)},
                {QStringLiteral("dabs"), dabs}};
    }
    QJsonObject operator()(const Apply& a) const {
        return {{QStringLiteral("op"), QStringLiteral("apply")},
                {QStringLiteral("layers"), indicesToJson(a.layers)}};
    }
    QJsonObject operator()(const Clear&) const {
        return {{QStringLiteral("op"), QStringLiteral("clear")}};
    }
    QJsonObject operator()(const Undo&) const {
        return {{QStringLiteral("op"), QStringLiteral("undo")}};
    }
    QJsonObject operator()(const Redo&) const {
        return {{QStringLiteral("op"), QStringLiteral("redo")}};
    }
};

}  // namespace

QJsonObject encode(const Op& op) {
    return std::visit(Encoder{}, op);
}

Op decode(const QJsonObject& json) {
    const QString op = json.value(QStringLiteral("op")).toString();
    if (op == QStringLiteral("start")) {
        Start s;
        const QJsonObject options = json.value(QStringLiteral("options")).toObject();
        s.options.prefilter = options.value(QStringLiteral("prefilter")).toBool();
        s.options.prefilterParams =
            paramsFromJson(options.value(QStringLiteral("prefilterParams")));
        s.layers = layersFromJson(json.value(QStringLiteral("layers")));
        // Older journals have no names.
        for (const QJsonValue& v : json.value(QStringLiteral("names")).toArray())
            s.names.push_back(v.toString().toStdString());
        // Older journals name no bank folder.
        s.bankDir = json.value(QStringLiteral("bank")).toString().toStdString();
        return s;
    }
    if (op == QStringLiteral("input")) return Input{};
    if (op == QStringLiteral("addLayer"))
        return AddLayer{json.value(QStringLiteral("filter")).toString().toStdString(),
                        paramsFromJson(json.value(QStringLiteral("params"))),
                        json.value(QStringLiteral("fill")).toBool()};
    if (op == QStringLiteral("addLayers"))
        return AddLayers{layersFromJson(json.value(QStringLiteral("layers")))};
    if (op == QStringLiteral("removeLayer")) return RemoveLayer{index(json, "index")};
    if (op == QStringLiteral("renameLayer"))
        return RenameLayer{index(json, "index"),
                           json.value(QStringLiteral("name")).toString().toStdString()};
    if (op == QStringLiteral("weights")) return Weights{index(json, "index")};
    if (op == QStringLiteral("fill"))
        return Fill{index(json, "index"), modeFromJson(json.value(QStringLiteral("mode")))};
    if (op == QStringLiteral("stroke")) {
        Stroke s;
        s.layer = index(json, "layer");
        s.brush = {json.value(QStringLiteral("size")).toDouble(),
                   json.value(QStringLiteral("softness")).toDouble()};
        s.mode = modeFromJson(json.value(QStringLiteral("mode")));
        for (const QJsonValue& v : json.value(QStringLiteral("dabs")).toArray())
            s.dabs.push_back(v.toDouble());
        return s;
    }
    if (op == QStringLiteral("apply")) {
        Apply a;
        for (const QJsonValue& v : json.value(QStringLiteral("layers")).toArray())
            a.layers.push_back(std::size_t(v.toInteger()));
        return a;
    }
    if (op == QStringLiteral("clear")) return Clear{};
    if (op == QStringLiteral("undo")) return Undo{};
    if (op == QStringLiteral("redo")) return Redo{};
    throw Error(ErrorKind::Format, "unknown journal operation \"" + op.toStdString() + "\"");
}

namespace {

// A line's keys but "op" as a session's view state (string values).
std::map<std::string, std::string> stringsOf(const QJsonObject& json) {
    std::map<std::string, std::string> state;
    for (auto it = json.begin(); it != json.end(); ++it)
        if (it.key() != QStringLiteral("op"))
            // A number is read as its text, so that the strict reader sees what was written.
            state[it.key().toStdString()] = it.value().toVariant().toString().toStdString();
    return state;
}

// A line of operation `op` holding `state` (a session's view-state keys).
QJsonObject lineOf(const QString& op, const std::map<std::string, std::string>& state) {
    QJsonObject json{{QStringLiteral("op"), op}};
    for (const auto& [key, value] : state)
        json.insert(QString::fromStdString(key), QString::fromStdString(value));
    return json;
}

}  // namespace

QJsonObject encodeSettings(const render::Settings& settings) {
    // The session file's keys and spelling (session_state), one line.
    std::map<std::string, std::string> state;
    writeDocumentState({}, settings, state);
    return lineOf(QStringLiteral("settings"), state);
}

render::Settings decodeSettings(const QJsonObject& json, render::Settings settings,
                                const std::string& file, const std::string& where) {
    return readSettings(stringsOf(json), settings, file, where + "/");
}

QJsonObject encodeReference(const std::optional<ReferenceInfo>& info) {
    std::map<std::string, std::string> state;
    if (info) writeReferenceState(*info, state);
    return lineOf(QStringLiteral("reference"), state);
}

std::optional<ReferenceInfo> decodeReference(const QJsonObject& json,
                                             const std::vector<render::LookItem>& look) {
    return readReferenceState(stringsOf(json), look);
}

QJsonObject encodeRegion(const std::vector<double>& lasso) {
    QJsonArray points;
    for (double v : lasso) points.append(v);
    return {{QStringLiteral("op"), QStringLiteral("region")}, {QStringLiteral("lasso"), points}};
}

std::vector<double> decodeRegion(const QJsonObject& json) {
    std::vector<double> lasso;
    for (const QJsonValue& v : json.value(QStringLiteral("lasso")).toArray()) {
        if (!v.isDouble() || !std::isfinite(v.toDouble()))
            throw Error(ErrorKind::Format,
                        "the region's lasso holds something other than a finite number");
        lasso.push_back(v.toDouble());
    }
    if (lasso.size() % 2 != 0)
        throw Error(ErrorKind::Format, "the region's lasso has an odd count of coordinates");
    return lasso;
}

QJsonObject encodeView(const View& view) {
    QJsonObject json{{QStringLiteral("op"), QStringLiteral("view")},
                     {QStringLiteral("exposure"), view.exposure},
                     {QStringLiteral("keepRefining"), view.keepRefining}};
    if (view.stage) json.insert(QStringLiteral("stage"), *view.stage);
    if (view.channel) json.insert(QStringLiteral("channel"), QString::fromStdString(*view.channel));
    return json;
}

View decodeView(const QJsonObject& json) {
    const QJsonValue exposure = json.value(QStringLiteral("exposure"));
    const QJsonValue refining = json.value(QStringLiteral("keepRefining"));
    if (!exposure.isDouble() || !std::isfinite(exposure.toDouble()))
        throw Error(ErrorKind::Format, "the view's exposure is not a finite number of stops");
    if (!refining.isBool())
        throw Error(ErrorKind::Format, "the view's keepRefining is not true or false");
    View view{exposure.toDouble(), refining.toBool(), std::nullopt, std::nullopt};
    if (const QJsonValue stage = json.value(QStringLiteral("stage")); !stage.isUndefined()) {
        const double s = stage.toDouble(-1.0);
        if (!stage.isDouble() || !(s >= 0.0 && s < kStages) || s != std::floor(s))
            throw Error(ErrorKind::Format, "the view's stage is not an integer in [0, " +
                                               std::to_string(kStages) + ")");
        view.stage = int(s);
    }
    if (const QJsonValue channel = json.value(QStringLiteral("channel")); !channel.isUndefined()) {
        if (!channel.isString())
            throw Error(ErrorKind::Format, "the view's channel is not a channel's name");
        view.channel = channel.toString().toStdString();
    }
    return view;
}

QJsonObject encodeSetLook(const std::string& item, const std::string& property,
                          const std::array<double, 3>& value) {
    return {{QStringLiteral("op"), QStringLiteral("setLook")},
            {QStringLiteral("item"), QString::fromStdString(item)},
            {QStringLiteral("property"), QString::fromStdString(property)},
            {QStringLiteral("value"), QJsonArray{value[0], value[1], value[2]}}};
}

}  // namespace glint::studio::journal_codec
