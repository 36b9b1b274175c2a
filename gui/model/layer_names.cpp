#include "model/layer_names.h"

#include <QObject>
#include <QStringList>

#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"

namespace glint::studio {

namespace {

// How each filter is named, and the parameter that tells two layers of it apart.
struct Naming {
    const char* filter;
    const char* title;
    const char* param;   // the main parameter
    const char* symbol;  // its symbol in the name; empty: a word for its strength
};

constexpr Naming kNamings[] = {
    {"gaussian", "Gaussian", "sigma", "σ"},
    {"bilateral", "Bilateral", "sigmaS", "σs"},
    {"bilateral-mc", "Bilateral (sampled)", "sigmaS", "σs"},
    {"cross-bilateral", "Cross-bilateral", "sigmaS", "σs"},
    {"guided", "Guided", "radius", "r"},
    {"nlmeans", "Non-local means", "strength", ""},
    {"nfor", "NFOR (regression)", "strength", ""},
    {"external", "External denoiser", "", ""},
    {"unet", "Learned (unet)", "quality", ""},
    {"identity", "No filter (the render)", "", ""},
    {denoise::kAutoCorrection, "Auto's correction", "", ""},  // no filter: Auto Start's layer
};

const Naming* namingOf(const std::string& filter) {
    for (const Naming& n : kNamings)
        if (filter == n.filter) return &n;
    return nullptr;
}

QString number(double v) {
    return QString::number(v, 'g', 3);
}

// "mild", "medium" or "strong": the value against the parameter's default.
QString strengthWord(double value, double defaultValue) {
    if (defaultValue > 0.0 && value < 0.67 * defaultValue) return QObject::tr("mild");
    if (defaultValue > 0.0 && value > 1.5 * defaultValue) return QObject::tr("strong");
    return QObject::tr("medium");
}

const denoise::Filter* filterNamed(const std::string& name) {
    for (const denoise::Filter* f : denoise::allFilters())
        if (f->name() == name) return f;
    return nullptr;
}

}  // namespace

QString filterTitle(const std::string& filter) {
    if (const Naming* naming = namingOf(filter)) return QString::fromUtf8(naming->title);
    QString title = QString::fromStdString(filter);
    if (!title.isEmpty()) title[0] = title[0].toUpper();
    return title;
}

QString shortParamLabel(const denoise::ParamSpec& spec) {
    // "spatial sigma (px)" -> "spatial sigma", "strength k" -> "strength".
    QString label = QString::fromStdString(spec.label);
    const qsizetype paren = label.indexOf(QStringLiteral(" ("));
    if (paren > 0) label.truncate(paren);
    const qsizetype space = label.lastIndexOf(QLatin1Char(' '));
    if (space > 0 && label.size() - space == 2) label.truncate(space);
    return label.isEmpty() ? QString::fromStdString(spec.name) : label;
}

QString paramValueText(const denoise::ParamSpec& spec, double value, int digits) {
    if (spec.isChoice()) return QString::fromStdString(denoise::formatParamValue(spec, value));
    return QString::number(value, 'g', spec.integer ? 10 : digits);
}

QString choiceName(const std::string& filter, const denoise::ParamValues& params) {
    const QString title = filterTitle(filter);
    const Naming* naming = namingOf(filter);
    const denoise::Filter* f = filterNamed(filter);
    if (!naming || !f || !*naming->param) return title;
    const auto it = params.find(naming->param);
    const denoise::ParamSpec* spec = denoise::findParam(f->params(), naming->param);
    if (it == params.end() || !spec) return title;
    // A choice by its option's name; a number by its short label and 2 significant digits.
    if (spec->isChoice())
        return QStringLiteral("%1, %2").arg(title, paramValueText(*spec, it->second));
    return QStringLiteral("%1, %2 %3")
        .arg(title, shortParamLabel(*spec), paramValueText(*spec, it->second));
}

QString layerName(const std::string& filter, const denoise::ParamValues& params) {
    const Naming* naming = namingOf(filter);
    const QString title = filterTitle(filter);
    if (!naming || !*naming->param) return title;
    const denoise::Filter* f = filterNamed(filter);
    const auto it = params.find(naming->param);
    if (!f || it == params.end()) return title;
    for (const denoise::ParamSpec& spec : f->params())
        if (spec.name == naming->param) {
            // A choice by its option's name ("Learned (unet), fast"); a number by its symbol
            // or a word for its strength.
            const QString detail =
                spec.isChoice()
                    ? QString::fromStdString(denoise::formatParamValue(spec, it->second))
                : *naming->symbol ? QStringLiteral("%1 %2").arg(QString::fromUtf8(naming->symbol),
                                                                number(it->second))
                                  : strengthWord(it->second, spec.defaultValue);
            return QStringLiteral("%1, %2").arg(title, detail);
        }
    return title;
}

QString layerParameters(const std::string& filter, const denoise::ParamValues& params) {
    QStringList lines{
        QStringLiteral("%1 (%2)").arg(layerName(filter, params), QString::fromStdString(filter))};
    if (filter == denoise::kAutoCorrection)
        lines << QObject::tr(
            "What takes the blend of the layers beneath to auto's result (the stacking's "
            "correction): painted away, the blend shows");
    const denoise::Filter* f = filterNamed(filter);
    if (!f) return lines.join(QLatin1Char('\n'));
    for (const denoise::ParamSpec& spec : f->params()) {
        if (!params.count(spec.name) && !params.strings.count(spec.name)) continue;
        lines << QStringLiteral("%1 (%2): %3")
                     .arg(QString::fromStdString(spec.label), QString::fromStdString(spec.name),
                          QString::fromStdString(denoise::paramSummary(spec, params)));
    }
    return lines.join(QLatin1Char('\n'));
}

}  // namespace glint::studio
