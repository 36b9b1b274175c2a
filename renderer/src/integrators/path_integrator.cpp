#include "integrators/path_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "integrators/surface_inputs.h"
#include "materials/bsdf.h"
#include "sampling/mlt_sampler.h"
#include "sampling/sobol.h"
#include "sampling/stratified_sampler.h"

namespace glint::render {

namespace {
constexpr float kInfinity = std::numeric_limits<float>::infinity();
/// BLEND surfaces one bounce's ray passes on its sampler's number; past them, the hash decides.
constexpr int kMaxBlendPasses = 64;
/// The narrowest interval a BLEND choice's number may have been rescaled from: 2^-12 leaves
/// it 12 of a float's 24 bits.
constexpr float kMinBlendWidth = 0x1p-12f;
/// The largest float below 1 (rescaled numbers must stay in [0, 1)).
constexpr float kBelowOne = 0x1.fffffep-1f;

/// True when some material of the scene is alphaMode BLEND.
bool hasBlend(const detail::SceneData& scene) {
    return std::any_of(scene.materials.begin(), scene.materials.end(),
                       [](const auto& m) { return m.alphaMode == detail::AlphaMode::Blend; });
}

/// Surface data at a hit: the point, its geometric and shading normals, and the material's
/// inputs and emission there.
struct Shading {
    Vec3 p, ng, ns;
    SurfaceInputs inputs;
    Vec3 emission;  ///< set where the material is emissive
    /// The hit reads textures or vertex colours (readsSurface): its inputs may differ from the
    /// material's factors.
    bool textured = false;
};

/// The point at barycentrics (1 - u - v, u, v) of corners a, b, c.
[[gnu::always_inline]] inline Vec3 atBarycentrics(const Vec3& a, const Vec3& b, const Vec3& c,
                                                  float b0, float u, float v) {
    return a * b0 + b * u + c * v;
}

/// Sets s.p, s.ng and s.ns from a triangle's corners p0..p2, unit normal ng and vertex normals
/// n (null: none) at barycentrics (b0, u, v).
[[gnu::always_inline]] inline void setGeometry(Shading& s, const Vec3& p0, const Vec3& p1,
                                               const Vec3& p2, const Vec3& ng, const Vec3* n0,
                                               const Vec3* n1, const Vec3* n2, float b0, float u,
                                               float v) {
    s.p = atBarycentrics(p0, p1, p2, b0, u, v);
    s.ng = ng;
    s.ns = ng;
    if (n0) {
        const Vec3 ns = atBarycentrics(*n0, *n1, *n2, b0, u, v);
        const float len = length(ns);
        if (len > 0.0f) {
            s.ns = ns / len;
            // The geometric normal follows the shading normal's side (PBR 2.10.1).
            if (dot(s.ng, s.ns) < 0.0f) s.ng = -s.ng;
        }
    }
}

/// True when a hit on `mesh` with `material` reads more than the material's factors: a texture
/// through the mesh's texture coordinates, or the mesh's vertex colours times its base colour.
/// Elsewhere evaluateInputs and emissionAt give the factors and applyNormalMap leaves the
/// normal as it is, so a plain hit needs no SurfacePoint.
[[gnu::always_inline]] inline bool readsSurface(const detail::Mesh& mesh,
                                                const detail::Material& material) {
    if (material.textureTimesFactor && !mesh.colors.empty()) return true;
    return !mesh.uvs.empty() && (usesTextures(material) || material.transmissionMap.present());
}

/// What a hit that reads textures or vertex colours (readsSurface) takes from them: its shading
/// normal bent by a normal or bump map, its inputs and its emission.
struct TexturedSurface {
    Vec3 ns;
    SurfaceInputs inputs;
    Vec3 emission;
};

/// The TexturedSurface of `hit` at p on `mesh` with `material`, whose shading normal (on the
/// viewer's side) is `ns`: its SurfacePoint (both texture coordinate sets and their footprints)
/// looked up in the material's textures. Out of line: plain hits never come here.
TexturedSurface texturedSurface(const detail::SceneData& scene, const detail::Mesh& mesh,
                                const Hit& hit, const detail::Material& material, const Vec3& p,
                                const Vec3& ns, float time, const Camera& camera,
                                bool seenSharply) {
    SurfacePoint at;
    const detail::SurfaceId id = hit.surface;
    at.id = id;
    at.b1 = hit.u;
    at.b2 = hit.v;
    at.hasUv = !mesh.uvs.empty();
    if (at.hasUv) at.uv = detail::surfaceUv(mesh, 0, id.prim, hit.u, hit.v);
    at.hasUv1 = !mesh.uvs1.empty();
    if (at.hasUv1) at.uv1 = detail::surfaceUv(mesh, 1, id.prim, hit.u, hit.v);
    if (at.hasUv && !seenSharply) {
        // After a diffuse or glossy bounce: a widened footprint, the resident levels in memory.
        at.footprint = at.footprint1 = detail::kCoarseFootprint;
    } else if (at.hasUv && usesTextures(material)) {
        // The texture footprint: a pixel's step as seen from the camera (docs/assets.md).
        // The triangle again (only here: textured hits seen sharply), for its edges.
        const detail::TriangleView tri = scene.triangle(id.instance, id.prim, time);
        Vec3 dpdx, dpdy;
        camera.footprintAxes(p, tri.ng, time, dpdx, dpdy);
        const std::uint32_t* idx = &mesh.indices[3 * std::size_t(id.prim)];
        at.footprint =
            uvFootprint(tri, mesh.uvs[idx[0]], mesh.uvs[idx[1]], mesh.uvs[idx[2]], dpdx, dpdy);
        // The second set's own footprint: its uvs change at their own rate over the triangle.
        if (at.hasUv1)
            at.footprint1 = uvFootprint(tri, mesh.uvs1[idx[0]], mesh.uvs1[idx[1]],
                                        mesh.uvs1[idx[2]], dpdx, dpdy);
    }
    TexturedSurface t;
    // Only a normal or bump map bends the normal.
    t.ns = material.normalMap.present() || material.bumpMap.present()
               ? applyNormalMap(scene, material, at, ns)
               : ns;
    t.inputs = evaluateInputs(scene, material, at);
    t.emission = material.emissive() ? emissionAt(scene, material, at) : material.emission;
    return t;
}

/// The shading data of `hit` on a surface of `material` seen from wo (the ray's shutter time
/// `time`; `seenSharply`: by the camera or through specular bounces only; `transmits`: the
/// material's BsdfFlags::transmits). A plain hit (not readsSurface) takes the material's
/// factors, emission and the geometry's normal as they are.
[[gnu::always_inline]] inline Shading shade(const detail::SceneData& scene, const Hit& hit,
                                            const detail::Material& material, bool transmits,
                                            const Vec3& wo, float time, const Camera& camera,
                                            bool seenSharply) {
    Shading s;
    const detail::SurfaceId id = hit.surface;
    // The instance and its mesh, found once for the corners and texture coordinates.
    const detail::Instance& inst = scene.instances[id.instance];
    const detail::Mesh& mesh = scene.meshes[inst.mesh];
    const float b0 = 1.0f - hit.u - hit.v;
    if (inst.motion < 0 && inst.identity) {
        // A mesh in world space: its corners and face normal read in place (the same values
        // as worldTriangle's, without filling a TriangleView).
        const std::uint32_t* idx = &mesh.indices[3 * std::size_t(id.prim)];
        const Vec3 &p0 = mesh.positions[idx[0]], &p1 = mesh.positions[idx[1]],
                   &p2 = mesh.positions[idx[2]];
        const Vec3 ng = detail::faceNormal(mesh, id.prim, p0, p1, p2);
        const bool hasNormals = !mesh.normals.empty();
        setGeometry(s, p0, p1, p2, ng, hasNormals ? &mesh.normals[idx[0]] : nullptr,
                    hasNormals ? &mesh.normals[idx[1]] : nullptr,
                    hasNormals ? &mesh.normals[idx[2]] : nullptr, b0, hit.u, hit.v);
    } else {
        // The triangle in world space at the ray's shutter time (moving instances are posed).
        const detail::TriangleView tri = scene.posedTriangle(inst, id.prim, time);
        setGeometry(s, tri.p[0], tri.p[1], tri.p[2], tri.ng, tri.hasNormals ? &tri.n[0] : nullptr,
                    tri.hasNormals ? &tri.n[1] : nullptr, tri.hasNormals ? &tri.n[2] : nullptr, b0,
                    hit.u, hit.v);
    }
    // Surfaces that do not transmit are two-sided: face the normals towards the viewer. Those
    // that do (glass; glTF transmission) keep their normals outside, so that which side wo
    // lies on tells inside from outside.
    if (!transmits && dot(wo, s.ng) < 0.0f) {
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
    s.textured = readsSurface(mesh, material);
    if (s.textured) {
        const TexturedSurface t =
            texturedSurface(scene, mesh, hit, material, s.p, s.ns, time, camera, seenSharply);
        s.ns = t.ns;
        s.inputs = t.inputs;
        s.emission = t.emission;
    } else {
        s.inputs = factorInputs(material);
        s.emission = material.emission;
    }
    return s;
}

}  // namespace

PathIntegrator::PathIntegrator(const detail::SceneData& scene, const EmbreeScene& embree,
                               const LightSampler& lights, const Camera& camera,
                               const Settings& settings)
    : m_scene(scene),
      m_embree(embree),
      m_lights(lights),
      m_camera(camera),
      m_mis(settings.mis),
      m_useLightSampling(!lights.empty() && (settings.mis != MisHeuristic::None ||
                                             settings.strategy == Strategy::Light)),
      m_useBsdfHits(settings.mis != MisHeuristic::None || settings.strategy == Strategy::Bsdf),
      m_hasBlend(hasBlend(scene)),
      m_maxDepth(settings.maxDepth),
      m_rrDepth(settings.rrDepth) {
    // Where each instance's materials are (as SceneData::materialOf finds them).
    m_instanceMaterials.reserve(scene.instances.size());
    for (const detail::Instance& inst : scene.instances) {
        const std::vector<std::uint32_t>& materials = scene.meshes[inst.mesh].materials;
        InstanceMaterials m;
        if (inst.material >= 0)
            m.only = &scene.materials[std::size_t(inst.material)];
        else if (materials.size() == 1)
            m.only = &scene.materials[materials[0]];
        else
            m.perTriangle = materials.data();
        m_instanceMaterials.push_back(m);
    }
    // What each material's BSDF does, asked once: every hit and prefetch reads it.
    m_materialFlags.reserve(scene.materials.size());
    for (const detail::Material& m : scene.materials) m_materialFlags.push_back(materialFlags(m));
}

float PathIntegrator::misWeight(float pdf, float other) const {
    if (m_mis == MisHeuristic::None) return 1.0f;
    if (!(pdf > 0.0f)) return 0.0f;
    // Balance: p/(p+q); power (β = 2): p²/(p²+q²), as 1/(1+(q/p)^β) to avoid overflow
    // (Veach 1997, eqs. 9.12 and 9.13).
    const float r = other / pdf;
    return m_mis == MisHeuristic::Balance ? 1.0f / (1.0f + r) : 1.0f / (1.0f + r * r);
}

template <PathSampler Sampler>
bool PathIntegrator::meetsBlend(PathState& p, const Hit& hit, Sampler& rng) const {
    const detail::SurfaceId id = hit.surface;
    const float alpha = surfaceAlpha(m_scene, id.instance, id.prim, hit.u, hit.v);
    // The bounce's component number; past the cap, or with too few bits left, the hash's.
    if (!p.blendDrawn) {
        p.blendU = rng.bounce1D(p.depth, BounceDim::BsdfComponent);
        p.blendWidth = 1.0f;
        p.blendDrawn = true;
    } else if (p.blendPasses >= kMaxBlendPasses || p.blendWidth < kMinBlendWidth) {
        p.blendU = blendHash(p.ray.origin, p.ray.dir, id.instance, id.prim);
        p.blendWidth = 1.0f;
    }
    if (p.blendU < alpha) {
        p.blendU = std::min(p.blendU / alpha, kBelowOne);
        return true;
    }
    p.blendU = std::min((p.blendU - alpha) / (1.0f - alpha), kBelowOne);
    p.blendWidth *= 1.0f - alpha;
    ++p.blendPasses;
    // Continue from the far side of the surface (the triangle as the ray met it).
    const detail::TriangleView tri = m_scene.triangle(id.instance, id.prim, p.ray.time);
    const Vec3 at = tri.p[0] * (1.0f - hit.u - hit.v) + tri.p[1] * hit.u + tri.p[2] * hit.v;
    p.ray.origin = offsetRayOrigin(at, tri.ng, p.ray.dir, m_scene.extent);
    return false;
}

template <PathSampler Sampler>
void PathIntegrator::advance(PathState& p, bool found, const Hit& hit,
                             const detail::Material* material, Sampler& rng,
                             std::uint64_t& rays) const {
    p.shadowPending = false;
    p.alive = false;
    const Ray& ray = p.ray;
    const int depth = p.depth;
    if (!found) {
        // Escaped: environment radiance, MIS-weighted against environment sampling.
        if (const Environment* env = m_lights.environment()) {
            const Vec3 le = env->eval(ray.dir);
            if (depth == 0 || p.specularBounce) {
                p.radiance += p.beta * le;
            } else if (m_useBsdfHits) {
                const float lightPdf = m_useLightSampling ? m_lights.pdfEnvironment(ray.dir) : 0.0f;
                p.radiance += p.beta * le * misWeight(p.prevPdf, lightPdf);
            }
        }
        return;
    }
    // A BLEND surface the ray passes: the same bounce goes on beyond it (p.ray moved).
    const detail::Material& mat = *material;
    if (m_hasBlend && mat.alphaMode == detail::AlphaMode::Blend && !meetsBlend(p, hit, rng)) {
        p.alive = true;
        return;
    }
    const Vec3 wo = -ray.dir;
    const BsdfFlags& flags = flagsOf(mat);
    const Shading sh = shade(m_scene, hit, mat, flags.transmits, wo, ray.time, m_camera,
                             depth == 0 || p.specularBounce);

    // Emission found by the camera ray, a specular bounce or BSDF sampling (MIS).
    if (mat.emissive()) {
        const Vec3& le = sh.emission;
        if (depth == 0 || p.specularBounce) {
            p.radiance += p.beta * le;
        } else if (m_useBsdfHits) {
            const float lightPdf =
                m_useLightSampling ? m_lights.pdfArea(hit.surface, p.prevP, sh.p, sh.ng) : 0.0f;
            p.radiance += p.beta * le * misWeight(p.prevPdf, lightPdf);
        }
    }

    const SurfaceInputs& inputs = sh.inputs;
    const Vec3& albedo = inputs.albedo;
    const Bsdf bsdf = Bsdf::at(mat, flags, inputs);
    const bool specular = bsdf.isSpecular();
    // A transmitting material keeps its normals outside; where its BSDF is opaque (a texel of
    // zero transmission) the surface is two-sided as any other: face it to the viewer.
    const bool passes = bsdf.transmits();
    // (Only a textured hit can differ: elsewhere shade() has faced them to the viewer already.)
    Vec3 ng = sh.ng, ns = sh.ns;
    if (sh.textured && !passes && dot(wo, ng) < 0.0f) {
        ng = -ng;
        ns = -ns;
    }
    if (!p.featuresDone && !specular) {
        p.out.albedo = albedo;
        // The normal on the viewer's side, for glass seen from inside too.
        p.out.normal = passes && dot(wo, ns) < 0.0f ? -ns : ns;
        p.out.depth = m_camera.depth(sh.p, ray.time);
        p.out.position = sh.p;
        p.featuresDone = true;
    }
    if (depth >= m_maxDepth) return;

    Frame frame = Frame::fromNormal(ns);
    Vec3 woLocal = frame.toLocal(wo);
    if (!passes && woLocal.z <= 0.0f) {
        // Shading normal faces away from the viewer: fall back to the geometric normal.
        frame = Frame::fromNormal(ng);
        woLocal = frame.toLocal(wo);
    }

    // Next-event estimation at non-specular vertices (Veach 1997, sec. 9.2): the contribution
    // is weighed now, with this bounce's throughput, and counts times the fraction its shadow
    // ray lets through (EmbreeScene::visibility).
    // A transmitting surface also takes light from behind it (wi.z < 0 in the local frame).
    if (!specular && m_useLightSampling) {
        LightSample ls;
        const float uSelect = rng.bounce1D(depth, BounceDim::LightSelect);
        const Vec2 uLight = rng.bounce2D(depth, BounceDim::LightPoint);
        if (m_lights.sample(sh.p, uSelect, uLight, ls) && (passes || dot(ls.wi, ng) > 0.0f)) {
            const Vec3 wiLocal = frame.toLocal(ls.wi);
            // f and its density together: the MIS weight below needs the density.
            const BsdfValue value = bsdf.evaluate(woLocal, wiLocal);
            const Vec3 f = value.f * std::abs(wiLocal.z);
            if (!isBlack(f) && !isBlack(ls.radiance)) {
                const Vec3 origin = offsetRayOrigin(sh.p, sh.ng, ls.wi, m_scene.extent);
                float tMax = kInfinity;
                Vec3 dir = ls.wi;
                if (std::isfinite(ls.distance)) {  // not the environment nor a directional light
                    const Vec3 d = ls.point - origin;
                    const float dist = length(d);
                    dir = d / dist;
                    tMax = dist - rayEpsilon(ls.point, m_scene.extent);
                }
                ++rays;
                if (tMax > 0.0f) {
                    // A delta light has no BSDF-sampling strategy to weigh against.
                    const float w =
                        m_useBsdfHits && !ls.delta ? misWeight(ls.pdf, value.pdf) : 1.0f;
                    p.shadowContribution = p.beta * f * ls.radiance * (w / ls.pdf);
                    p.shadow = ShadowRay{origin, dir, tMax, ray.time};
                    p.shadowPending = true;
                }
            }
        }
    }

    // Continue the path by sampling the BSDF.
    // A slotted sampler skips the numbers this BSDF does not read (the others never shift); a
    // stream sampler draws both, so that its later numbers stay where they were.
    BsdfSample bs;
    constexpr bool slotted = Sampler::kSlotted;
    Vec2 uBsdf{};
    float uc = 0.0f;
    if (!slotted || bsdf.readsDirectionPair())
        uBsdf = rng.bounce2D(depth, BounceDim::BsdfDirection);
    // After a BLEND choice the component number is what the choice left of it (meetsBlend).
    if (p.blendDrawn)
        uc = p.blendU;
    else if (!slotted || bsdf.readsComponentNumber())
        uc = rng.bounce1D(depth, BounceDim::BsdfComponent);
    if (!bsdf.sample(woLocal, uBsdf, uc, bs)) return;
    // bs.wi is unit and the frame orthonormal: only rounding is left to correct.
    const Vec3 wi = renormalize(frame.toWorld(bs.wi));
    if (!passes && dot(wi, ng) <= 0.0f) return;
    p.beta *= bs.weight;
    if (isBlack(p.beta)) return;

    // Russian roulette (PBR 14.5.1) with survival probability √(max throughput channel), as
    // Cycles does: paths end later than with the throughput itself, which on the Cornell
    // box lowers the relMSE at 64 spp by 19 % for 4 % fewer samples per second
    // (docs/lab/renderer.md, "Where the error per sample came from").
    if (depth + 1 > m_rrDepth) {
        const float survive = std::min(1.0f, std::sqrt(maxComponent(p.beta)));
        if (rng.bounce1D(depth, BounceDim::Roulette) >= survive) return;
        // Divide (not multiply by 1/survive): a denormal survival probability would make
        // the reciprocal Inf and the throughput NaN.
        p.beta = p.beta / survive;
    }
    p.specularBounce = bs.specular;
    p.prevPdf = bs.pdf;
    p.prevP = sh.p;
    p.ray.origin = offsetRayOrigin(sh.p, sh.ng, wi, m_scene.extent);
    p.ray.dir = wi;
    p.depth = depth + 1;
    p.blendDrawn = false;
    p.blendPasses = 0;
    p.alive = true;
}

unsigned PathIntegrator::numbersNeeded(const PathState& p, const detail::Material& mat) const {
    auto bit = [](BounceDim slot) { return slotBit(slot); };
    // A BLEND surface's choice reads the component number (meetsBlend).
    const unsigned blend = m_hasBlend && mat.alphaMode == detail::AlphaMode::Blend && !p.blendDrawn
                               ? bit(BounceDim::BsdfComponent)
                               : 0u;
    if (p.depth >= m_maxDepth) return blend;
    unsigned slots = blend;
    // What the material's BSDF reads (advance: sample()'s numbers, next-event estimation where
    // it is not specular); its textures never change that.
    const BsdfFlags& flags = flagsOf(mat);
    if (flags.directionPair) slots |= bit(BounceDim::BsdfDirection);
    if (flags.componentNumber) slots |= bit(BounceDim::BsdfComponent);
    if (!flags.specular && m_useLightSampling)
        slots |= bit(BounceDim::LightSelect) | bit(BounceDim::LightPoint);
    if (p.depth + 1 > m_rrDepth) slots |= bit(BounceDim::Roulette);
    return slots;
}

template <PathSampler Sampler>
void PathIntegrator::trace(const Ray& cameraRay, Sampler& rng, FilmSample& out,
                           std::uint64_t& rays) const {
    PathState p;
    p.ray = cameraRay;
    while (p.alive) {
        Hit hit;
        ++rays;
        const bool found = m_embree.intersect(p.ray, kInfinity, hit, p.depth == 0);
        advance(p, found, hit, found ? &materialAt(hit) : nullptr, rng, rays);
        // The light's contribution, times the fraction its shadow ray lets through.
        if (p.shadowPending) {
            const float v =
                m_embree.visibility(p.shadow.origin, p.shadow.dir, p.shadow.tMax, p.shadow.time);
            if (v > 0.0f) p.radiance += p.shadowContribution * v;
        }
    }
    out = p.out;
    out.color = p.radiance;
}

namespace {
/// traceMany's working arrays, kept per thread (and sampler type) so that batches do not
/// allocate; each as long as the batch, written by index (a bounce fills a prefix of the
/// shadow and prefetch arrays).
template <PathSampler Sampler>
struct BatchScratch {
    std::vector<PathState> paths;
    std::vector<std::size_t> live, shadowed;
    std::vector<const Ray*> queries;
    std::vector<const ShadowRay*> shadowQueries;
    std::vector<Hit> hits;
    std::vector<const detail::Material*> materials;
    std::unique_ptr<bool[]> found;
    std::unique_ptr<float[]> visible;
    std::vector<Sampler*> prefetchSamplers;
    std::vector<int> prefetchDepths;
    std::vector<unsigned> prefetchSlots;
    std::size_t capacity = 0;

    void reset(std::size_t count) {
        paths.assign(count, PathState{});
        live.resize(count);
        queries.resize(count);
        hits.resize(count);
        materials.resize(count);
        shadowed.resize(count);
        shadowQueries.resize(count);
        prefetchSamplers.resize(count);
        prefetchDepths.resize(count);
        prefetchSlots.resize(count);
        if (count > capacity) {
            found.reset(new bool[count]);
            visible.reset(new float[count]);
            capacity = count;
        }
    }
};
}  // namespace

template <PathSampler Sampler>
void PathIntegrator::traceMany(std::size_t count, const Ray* cameraRays, Sampler* samplers,
                               FilmSample* out, std::uint64_t& rays) const {
    thread_local BatchScratch<Sampler> scratch;
    BatchScratch<Sampler>& b = scratch;
    b.reset(count);
    for (std::size_t i = 0; i < count; ++i) {
        b.paths[i].ray = cameraRays[i];
        b.live[i] = i;
    }
    for (bool first = true; !b.live.empty(); first = false) {
        // Every live path's ray (camera rays first, as a coherent query), then every shadow
        // ray its bounce left pending.
        const std::size_t n = b.live.size();
        for (std::size_t k = 0; k < n; ++k) b.queries[k] = &b.paths[b.live[k]].ray;
        rays += n;
        m_embree.intersectMany(n, b.queries.data(), b.hits.data(), b.found.get(), first);
        // Each hit's material, found once for the numbers it needs and for its shading; with a
        // PrefetchingSampler, this bounce's numbers of every path that hit something, computed
        // together.
        [[maybe_unused]] std::size_t prefetched = 0;
        for (std::size_t k = 0; k < n; ++k) {
            if (!b.found[k]) {
                b.materials[k] = nullptr;
                continue;
            }
            const detail::Material& material = materialAt(b.hits[k]);
            b.materials[k] = &material;
            if constexpr (PrefetchingSampler<Sampler>) {
                const PathState& p = b.paths[b.live[k]];
                b.prefetchSamplers[prefetched] = &samplers[b.live[k]];
                b.prefetchDepths[prefetched] = p.depth;
                b.prefetchSlots[prefetched] = numbersNeeded(p, material);
                ++prefetched;
            }
        }
        if constexpr (PrefetchingSampler<Sampler>)
            Sampler::prefetchMany(prefetched, b.prefetchSamplers.data(), b.prefetchDepths.data(),
                                  b.prefetchSlots.data());
        std::size_t shadowCount = 0;
        for (std::size_t k = 0; k < n; ++k) {
            PathState& p = b.paths[b.live[k]];
            advance(p, b.found[k], b.hits[k], b.materials[k], samplers[b.live[k]], rays);
            if (p.shadowPending) {
                b.shadowed[shadowCount] = b.live[k];
                b.shadowQueries[shadowCount] = &p.shadow;
                ++shadowCount;
            }
        }
        m_embree.visibilityMany(shadowCount, b.shadowQueries.data(), b.visible.get());
        for (std::size_t k = 0; k < shadowCount; ++k) {
            PathState& p = b.paths[b.shadowed[k]];
            if (b.visible[k] > 0.0f) p.radiance += p.shadowContribution * b.visible[k];
        }
        b.live.erase(std::remove_if(b.live.begin(), b.live.end(),
                                    [&](std::size_t i) { return !b.paths[i].alive; }),
                     b.live.end());
    }
    for (std::size_t i = 0; i < count; ++i) {
        out[i] = b.paths[i].out;
        out[i].color = b.paths[i].radiance;
    }
}

template void PathIntegrator::trace<StratifiedSampler>(const Ray&, StratifiedSampler&, FilmSample&,
                                                       std::uint64_t&) const;
template void PathIntegrator::trace<SobolSampler>(const Ray&, SobolSampler&, FilmSample&,
                                                  std::uint64_t&) const;
template void PathIntegrator::trace<ZSobolSampler>(const Ray&, ZSobolSampler&, FilmSample&,
                                                   std::uint64_t&) const;
template void PathIntegrator::trace<MltSampler>(const Ray&, MltSampler&, FilmSample&,
                                                std::uint64_t&) const;
template void PathIntegrator::traceMany<StratifiedSampler>(std::size_t, const Ray*,
                                                           StratifiedSampler*, FilmSample*,
                                                           std::uint64_t&) const;
template void PathIntegrator::traceMany<SobolSampler>(std::size_t, const Ray*, SobolSampler*,
                                                      FilmSample*, std::uint64_t&) const;
template void PathIntegrator::traceMany<ZSobolSampler>(std::size_t, const Ray*, ZSobolSampler*,
                                                       FilmSample*, std::uint64_t&) const;

}  // namespace glint::render
