// Paint scripts: read into typed layers and edits (every key and value checked with its JSON
// pointer), then replayed on a session.
#include "glint/denoise/paint_script.h"

#include <array>
#include <utility>

#include "glint/denoise/paint.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "json_reader.h"

namespace glint::denoise {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// Dab and seed coordinates beyond this many pixels are refused (they are meaningless and far
/// from any image Glint holds).
constexpr double kMaxCoordinate = 1e9;

/// One edit of the script, typed.
struct Edit {
    enum class Kind { Stroke, Fill, Diffuse, Weights };
    Kind kind = Kind::Weights;
    std::string where;                ///< its JSON pointer ("/edits/3/fill"), for late errors
    std::vector<std::size_t> layers;  ///< the layer edited (diffusion: the layers)
    BrushMode mode = BrushMode::Add;  ///< stroke, fill
    Brush brush;                      ///< stroke
    std::vector<std::array<double, 2>> points;  ///< stroke
    std::array<double, 2> seed{};               ///< fill
    WandOptions wand;                           ///< fill
    double value = 0.0;                         ///< weights
};

/// Reads the script's values; errors name the script and the JSON pointer.
class ScriptReader {
  public:
    ScriptReader(const std::string& file, std::size_t layerCount)
        : m_json(file), m_layerCount(layerCount) {}

    LayerSpec layer(const nlohmann::json& l, const std::string& where) const {
        m_json.requireObject(l, where, {"filter", "params"});
        const Filter* f = nullptr;
        try {
            f = &findFilter(m_json.string(m_json.at(l, "filter", where), where + "/filter"));
        } catch (const Error& e) {
            if (e.kind() == ErrorKind::Format) throw;
            m_json.fail(where + "/filter", e.message());
        }
        return {
            std::string(f->name()),
            params(*f, l.contains("params") ? l["params"] : nlohmann::json(), where + "/params")};
    }

    Edit edit(const nlohmann::json& edit, const std::string& where) const {
        if (!edit.is_object() || edit.size() != 1)
            m_json.fail(where,
                        "expected one of {\"stroke\": …}, {\"fill\": …}, {\"diffuse\": …}, "
                        "{\"weights\": …}, got " +
                            detail::describeJson(edit));
        const std::string kind = edit.begin().key();
        const nlohmann::json& e = edit.begin().value();
        const std::string at = where + "/" + kind;
        Edit out;
        out.where = at;
        if (kind == "stroke")
            stroke(e, at, out);
        else if (kind == "fill")
            fill(e, at, out);
        else if (kind == "diffuse")
            diffuse(e, at, out);
        else if (kind == "weights")
            weights(e, at, out);
        else
            m_json.fail(at,
                        "unknown edit '" + kind + "' (expected stroke, fill, diffuse or weights)");
        return out;
    }

  private:
    // Filter parameters: numbers, or option names for choice parameters.
    ParamValues params(const Filter& f, const nlohmann::json& given,
                       const std::string& where) const {
        ParamValues values;
        if (given.is_null()) return values;
        if (!given.is_object())
            m_json.fail(where,
                        "expected an object of parameters, got " + detail::describeJson(given));
        for (const auto& item : given.items()) {
            const std::string place = where + "/" + item.key();
            const ParamSpec* spec = findParam(f.params(), item.key());
            if (!spec) {
                // resolveParams words the error of an unknown name (it lists the valid ones).
                try {
                    resolveParams(f, {{item.key(), 0.0}});
                } catch (const Error& e) {
                    m_json.fail(place, e.message());
                }
                GLINT_CHECK(false, "resolveParams accepted an unknown parameter");
            }
            if (!item.value().is_string() && !spec->isStrings) {
                values[item.key()] = m_json.number(item.value(), place, spec->min, spec->max);
                continue;
            }
            // A name, a number as text, or a list of strings (an array, read as its JSON text).
            try {
                setParamFromText(*spec,
                                 item.value().is_string() ? item.value().get<std::string>()
                                                          : item.value().dump(),
                                 values);
            } catch (const Error& e) {
                m_json.fail(place, e.message());
            }
        }
        try {
            return resolveParams(f, values);
        } catch (const Error& e) {
            m_json.fail(where, e.message());
        }
    }

    std::size_t layerIndex(const nlohmann::json& v, const std::string& where) const {
        if (m_layerCount == 0) m_json.fail(where, "the script has no layers to edit");
        return std::size_t(m_json.integer(v, where, 0, std::int64_t(m_layerCount) - 1));
    }

    BrushMode mode(const nlohmann::json& e, const std::string& where) const {
        if (!e.contains("mode")) return BrushMode::Add;
        const nlohmann::json& m = e["mode"];
        if (m == "add") return BrushMode::Add;
        if (m == "subtract") return BrushMode::Subtract;
        m_json.fail(where + "/mode",
                    "expected \"add\" or \"subtract\", got " + detail::describeJson(m));
    }

    std::array<double, 2> point(const nlohmann::json& v, const std::string& where) const {
        m_json.array(v, where, 2);
        return {m_json.number(v[0], where + "/0", -kMaxCoordinate, kMaxCoordinate),
                m_json.number(v[1], where + "/1", -kMaxCoordinate, kMaxCoordinate)};
    }

    void stroke(const nlohmann::json& e, const std::string& at, Edit& out) const {
        m_json.requireObject(e, at, {"layer", "size", "softness", "mode", "points"});
        out.kind = Edit::Kind::Stroke;
        out.layers = {layerIndex(m_json.at(e, "layer", at), at + "/layer")};
        const nlohmann::json& size = m_json.at(e, "size", at);
        out.brush.size = m_json.number(size, at + "/size", 0.0, 1e5);
        if (out.brush.size <= 0.0)
            m_json.fail(at + "/size", "expected a brush diameter in (0, 1e5] pixels, got " +
                                          detail::describeJson(size));
        if (e.contains("softness"))
            out.brush.softness = m_json.number(e["softness"], at + "/softness", 0.0, 1.0);
        out.mode = mode(e, at);
        const nlohmann::json& points = m_json.array(m_json.at(e, "points", at), at + "/points");
        if (points.empty()) m_json.fail(at + "/points", "expected [[x, y], …], got []");
        for (std::size_t i = 0; i < points.size(); ++i)
            out.points.push_back(point(points[i], at + "/points/" + std::to_string(i)));
    }

    void fill(const nlohmann::json& e, const std::string& at, Edit& out) const {
        m_json.requireObject(e, at, {"layer", "mode", "wand"});
        out.kind = Edit::Kind::Fill;
        out.layers = {layerIndex(m_json.at(e, "layer", at), at + "/layer")};
        out.mode = mode(e, at);
        const std::string w = at + "/wand";
        const nlohmann::json& wand = m_json.at(e, "wand", at);
        m_json.requireObject(wand, w, {"seed", "color", "albedo", "normal", "depth"});
        out.seed = point(m_json.at(wand, "seed", w), w + "/seed");
        for (auto [key, field] : {std::pair{"color", &out.wand.color},
                                  {"albedo", &out.wand.albedo},
                                  {"normal", &out.wand.normal},
                                  {"depth", &out.wand.depth}})
            if (wand.contains(key)) *field = m_json.number(wand[key], w + "/" + key, -1e6, 1e6);
    }

    void diffuse(const nlohmann::json& e, const std::string& at, Edit& out) const {
        m_json.requireObject(e, at, {"layers"});
        out.kind = Edit::Kind::Diffuse;
        const nlohmann::json& layers = m_json.array(m_json.at(e, "layers", at), at + "/layers");
        if (layers.empty()) m_json.fail(at + "/layers", "expected [index, …], got []");
        for (std::size_t i = 0; i < layers.size(); ++i)
            out.layers.push_back(layerIndex(layers[i], at + "/layers/" + std::to_string(i)));
    }

    void weights(const nlohmann::json& e, const std::string& at, Edit& out) const {
        m_json.requireObject(e, at, {"layer", "value"});
        out.kind = Edit::Kind::Weights;
        out.layers = {layerIndex(m_json.at(e, "layer", at), at + "/layer")};
        out.value = m_json.number(m_json.at(e, "value", at), at + "/value", 0.0, 1.0);
    }

    detail::JsonReader m_json;
    std::size_t m_layerCount;
};

}  // namespace

struct PaintScript::Impl {
    std::string file;
    std::vector<LayerSpec> layers;
    std::vector<Edit> edits;

    void apply(Session& session, const Edit& e, std::size_t base) const;
};

PaintScript PaintScript::read(const fs::path& file) {
    return parse(detail::readJsonText(file, "paint script"), file.string());
}

PaintScript PaintScript::parse(const std::string& text, const std::string& file) {
    const json root = detail::parseJsonText(text, file);
    const detail::JsonReader reader(file);
    reader.requireObject(root, "", {"layers", "edits"});
    const json& layers = reader.array(reader.at(root, "layers", ""), "/layers");
    const ScriptReader script(file, layers.size());
    auto impl = std::make_shared<Impl>();
    impl->file = file;
    for (std::size_t i = 0; i < layers.size(); ++i)
        impl->layers.push_back(script.layer(layers[i], "/layers/" + std::to_string(i)));
    if (root.contains("edits")) {
        const json& edits = reader.array(root["edits"], "/edits");
        for (std::size_t i = 0; i < edits.size(); ++i)
            impl->edits.push_back(script.edit(edits[i], "/edits/" + std::to_string(i)));
    }
    PaintScript out;
    out.m_impl = std::move(impl);
    return out;
}

const std::vector<LayerSpec>& PaintScript::layers() const {
    return m_impl->layers;
}

std::size_t PaintScript::editCount() const {
    return m_impl->edits.size();
}

void PaintScript::apply(Session& session) const {
    const std::size_t base = session.layerCount();
    const detail::JsonReader reader(m_impl->file);
    for (std::size_t i = 0; i < m_impl->layers.size(); ++i) {
        // A filter the render cannot feed (a feature layer it lacks): name the script's layer.
        try {
            session.addLayer(m_impl->layers[i].filter, m_impl->layers[i].params);
        } catch (const Error& e) {
            if (e.kind() == ErrorKind::Cancelled) throw;
            reader.fail("/layers/" + std::to_string(i), e.message());
        }
    }
    for (const Edit& e : m_impl->edits) m_impl->apply(session, e, base);
}

void PaintScript::Impl::apply(Session& session, const Edit& e, std::size_t base) const {
    const detail::JsonReader reader(file);
    const std::size_t layer = base + e.layers.front();
    switch (e.kind) {
        case Edit::Kind::Stroke:
            session.beginStroke(layer, e.brush, e.mode);
            for (const auto& [x, y] : e.points) session.dab(x, y);
            session.endStroke();
            return;
        case Edit::Kind::Fill: {
            const auto [sx, sy] = e.seed;
            if (!(sx >= 0 && sx < session.width() && sy >= 0 && sy < session.height()))
                reader.fail(e.where + "/wand/seed",
                            "the seed lies outside the " + std::to_string(session.width()) + "x" +
                                std::to_string(session.height()) + " image");
            Image seeds(session.width(), session.height(), 1, 0.0f);
            seeds(int(sx), int(sy), 0) = 1.0f;
            session.fill(layer, magicWand(session.filterInput(), seeds, e.wand), e.mode);
            return;
        }
        case Edit::Kind::Diffuse: {
            std::vector<std::size_t> layers;
            for (std::size_t l : e.layers) layers.push_back(base + l);
            try {
                session.diffuse(layers);
            } catch (const Error& err) {
                if (err.kind() == ErrorKind::Cancelled) throw;
                reader.fail(e.where, err.message());
            }
            return;
        }
        case Edit::Kind::Weights:
            session.setWeights(layer, Image(session.width(), session.height(), 1, float(e.value)));
            return;
    }
}

}  // namespace glint::denoise
