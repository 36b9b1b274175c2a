// Tests of the material kinds (materials/material_kinds.h, MaterialKind in materials/bsdf.h):
// integrators know a material only by what its BSDF does (BsdfFlags), never by its kind; the
// flags a material reports before a hit is shaded are those of the BSDF of its factors; and
// evaluate()'s density is the one sample() draws with.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "materials/bsdf.h"
#include "materials/material_parameters.h"
#include "sampling/rng.h"
#include "source_text.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using detail::Material;
using detail::MaterialType;

/// Every registered kind's type.
std::vector<MaterialType> allTypes() {
    std::vector<MaterialType> types;
    for (std::size_t i = 0; i < std::size(kMaterialKinds); ++i)
        types.push_back(MaterialType(int(i)));
    return types;
}

/// Whether `code` holds `name` as a whole identifier.
bool namesWord(const std::string& code, const std::string& name) {
    const auto identifier = [](char c) { return std::isalnum((unsigned char)c) || c == '_'; };
    for (std::size_t at = code.find(name); at != std::string::npos; at = code.find(name, at + 1)) {
        const bool startsWord = at == 0 || !identifier(code[at - 1]);
        const std::size_t after = at + name.size();
        const bool endsWord = after >= code.size() || !identifier(code[after]);
        if (startsWord && endsWord) return true;
    }
    return false;
}

TEST(MaterialKinds, NoIntegratorSourceNamesAMaterialKind) {
    // The names a kind goes by in code: the enum, each value, each kind object and its
    // scene.json name (Bsdf::metallicRoughness would be one).
    std::set<std::string> names = {"MaterialType", "materialTypeName", "materialKind"};
#define GLINT_KIND_NAMES(Enum, object) \
    names.insert(#Enum);               \
    names.insert(#object);
    GLINT_MATERIAL_KINDS(GLINT_KIND_NAMES)
#undef GLINT_KIND_NAMES
    for (const MaterialType type : allTypes()) names.insert(materialKind(type).name);

    const fs::path dir = fs::path(GLINT_SOURCE_DIR) / "renderer/src/integrators";
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int files = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        ++files;
        const std::string code = test::codeOf(entry.path());
        for (const std::string& name : names) {
            EXPECT_FALSE(namesWord(code, name))
                << entry.path().filename().string() << " names '" << name
                << "': ask the material or its BSDF for its flags (materialFlags, Bsdf::flags)";
        }
    }
    EXPECT_GT(files, 0);
}

TEST(MaterialKinds, EveryKindHasItsOwnNameAndItsBsdfsFunctions) {
    std::set<std::string> seen;
    for (const MaterialType type : allTypes()) {
        const MaterialKind& kind = materialKind(type);
        SCOPED_TRACE(kind.name);
        EXPECT_TRUE(seen.insert(kind.name).second);
        EXPECT_STREQ(detail::materialTypeName(type), kind.name);
        EXPECT_NE(kind.flags, nullptr);
        EXPECT_NE(kind.evaluate, nullptr);
        EXPECT_NE(kind.sample, nullptr);
    }
}

TEST(MaterialKinds, TheDocsMaterialTableIsTheOneTheKindsGenerate) {
    // docs/scene-format.md's material table is materialParameterTable(), verbatim: a kind or a
    // parameter changed without the docs (or the reverse) fails here.
    const std::string table = materialParameterTable();
    EXPECT_NE(table.find("| `conductor` | `roughness` | number in [0, 1] | 0 |"), std::string::npos)
        << table;
    std::ifstream in(fs::path(GLINT_SOURCE_DIR) / "docs/scene-format.md");
    std::stringstream docs;
    docs << in.rdbuf();
    EXPECT_NE(docs.str().find(table), std::string::npos)
        << "docs/scene-format.md lacks the generated table; paste this into its \"materials\" "
           "section:\n"
        << table;
}

TEST(MaterialKinds, EveryParameterNamesTheFieldItFillsAndAUsableRange) {
    for (const MaterialType type : allTypes()) {
        const MaterialKind& kind = materialKind(type);
        for (const MaterialParameter& p : kind.parameters) {
            SCOPED_TRACE(std::string(kind.name) + "/" + p.spec.name);
            // Exactly one field, of the parameter's type.
            EXPECT_NE(p.colour == nullptr, p.number == nullptr);
            EXPECT_EQ(p.spec.isColour, p.colour != nullptr);
            EXPECT_LE(p.spec.min, p.spec.defaultValue);
            EXPECT_LE(p.spec.defaultValue, p.spec.max);
            EXPECT_FALSE(p.spec.label.empty());
            EXPECT_FALSE(p.spec.help.empty());
            // A pair names a partner of the same kind that names it back.
            if (p.partner) {
                const MaterialParameter* other = findParameter(kind, p.partner);
                ASSERT_NE(other, nullptr);
                ASSERT_NE(other->partner, nullptr);
                EXPECT_EQ(p.spec.name, other->partner);
            }
        }
    }
}

/// Materials of every kind at roughness 0 (the delta limits), at the smallest sampled roughness
/// and beyond, with and without transmission.
std::vector<Material> sampleMaterials() {
    std::vector<Material> materials;
    for (const MaterialType type : allTypes())
        for (const float roughness : {0.0f, 0.02f, 0.0317f, 0.5f})
            for (const float transmission : {0.0f, 0.6f}) {
                Material m;
                m.type = type;
                m.roughness = roughness;
                m.transmission = transmission;
                m.metallic = 0.2f;
                m.albedo = {0.7f, 0.5f, 0.3f};
                materials.push_back(m);
            }
    Material unbent;  // ior 1: the rough dielectric does not bend, and is the smooth one
    unbent.type = MaterialType::Dielectric;
    unbent.ior = 1.0f;
    unbent.roughness = 0.5f;
    materials.push_back(unbent);
    return materials;
}

std::string describe(const Material& m) {
    return std::string(detail::materialTypeName(m.type)) + ", roughness " +
           std::to_string(m.roughness) + ", transmission " + std::to_string(m.transmission) +
           ", ior " + std::to_string(m.ior);
}

TEST(MaterialKinds, AMaterialsFlagsAreThoseOfTheBsdfOfItsFactors) {
    // The integrator decides from materialFlags, before shading, which numbers a hit reads and
    // whether it keeps its normals outside; the BSDF built at the hit must agree.
    for (const Material& m : sampleMaterials()) {
        SCOPED_TRACE(describe(m));
        const BsdfFlags before = materialFlags(m);
        const BsdfFlags at = Bsdf::fromMaterial(m, m.albedo).flags;
        EXPECT_EQ(before.specular, at.specular);
        EXPECT_EQ(before.transmits, at.transmits);
        EXPECT_EQ(before.directionPair, at.directionPair);
        EXPECT_EQ(before.componentNumber, at.componentNumber);
        // A BSDF whose every event is a delta has no density to weigh lights against.
        if (at.specular) {
            const BsdfValue v =
                Bsdf::fromMaterial(m, m.albedo).evaluate({0.0f, 0.6f, 0.8f}, {0.0f, -0.6f, 0.8f});
            EXPECT_EQ(v.pdf, 0.0f);
            EXPECT_EQ(v.f.x + v.f.y + v.f.z, 0.0f);
        }
    }
}

TEST(MaterialKinds, EvaluateGivesTheDensityAndValueSampleUsed) {
    // For every non-specular BSDF: at a sampled direction, evaluate()'s pdf is the sample's, and
    // f |cos θi| / pdf its weight (fixed seed; relative tolerance 1e-4 for rounding).
    Rng rng(47);
    for (const Material& m : sampleMaterials()) {
        const Bsdf bsdf = Bsdf::fromMaterial(m, m.albedo);
        if (bsdf.isSpecular()) continue;
        SCOPED_TRACE(describe(m));
        const Vec3 wo = normalize(Vec3{0.3f, -0.2f, 0.9f});
        int checked = 0;
        for (int i = 0; i < 200; ++i) {
            BsdfSample s;
            const Vec2 u{rng.uniform(), rng.uniform()};
            if (!bsdf.sample(wo, u, rng.uniform(), s)) continue;
            const BsdfValue v = bsdf.evaluate(wo, s.wi);
            ASSERT_GT(v.pdf, 0.0f);
            EXPECT_NEAR(v.pdf, s.pdf, 1e-4f * s.pdf);
            const Vec3 weight = v.f * (std::abs(s.wi.z) / v.pdf);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(weight[c], s.weight[c], 1e-4f * s.weight[c]);
            ++checked;
        }
        EXPECT_GT(checked, 100);
    }
}

}  // namespace
}  // namespace glint::render
