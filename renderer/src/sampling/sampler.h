// What a sampler is to the path integrator (pbrt-v4's Sampler interface, as C++20 concepts):
// the numbers a path reads, named by bounce and slot. Every sampler — stratified/independent
// (sampling/stratified_sampler.h), Sobol and ZSobol (sampling/sobol.h), Metropolis
// (sampling/mlt_sampler.h) — satisfies PathSampler; the path tracer's pixel samplers also give
// the camera's numbers (PixelSampler); the Sobol sampler also computes a batch of paths' numbers
// ahead of use (PrefetchingSampler).
#pragma once

#include <concepts>
#include <cstddef>
#include <type_traits>

#include "vecmath.h"

namespace glint::render {

/// The numbers a bounce may read, in the order the path integrator reads them: light choice,
/// point on the light (pair), BSDF direction (pair), BSDF component, Russian roulette.
enum class BounceDim : int { LightSelect, LightPoint, BsdfDirection, BsdfComponent, Roulette };

/// True for the numbers of next-event estimation (light choice and point on the light).
constexpr bool isLightSlot(BounceDim slot) {
    return slot == BounceDim::LightSelect || slot == BounceDim::LightPoint;
}

/// A sampler of paths: bounce1D / bounce2D give the number(s) of bounce `depth` for `slot`.
/// `S::kSlotted` says where they come from. Slotted (Sobol, ZSobol): every slot of every bounce
/// has its own dimension, so a number the path does not read need not be drawn. Not slotted
/// (stratified, independent, Metropolis): the numbers come from streams in reading order (a pair
/// is two numbers, first x), so the path draws every number it might read, and a number it
/// skips never shifts the ones after it.
template <class S>
concept PathSampler = requires(S& sampler, int depth, BounceDim slot) {
    { sampler.bounce1D(depth, slot) } -> std::same_as<float>;
    { sampler.bounce2D(depth, slot) } -> std::same_as<Vec2>;
    typename std::bool_constant<S::kSlotted>;
};

/// A sampler of one camera sample of the path tracer: a PathSampler that also gives the
/// camera's numbers, camera2D(0) the film position in the pixel, camera2D(1) the lens point,
/// camera1D(2) the shutter time.
template <class S>
concept PixelSampler = PathSampler<S> && requires(S& sampler, int dim) {
    { sampler.camera2D(dim) } -> std::same_as<Vec2>;
    { sampler.camera1D(dim) } -> std::same_as<float>;
};

/// The bit of `slot` in the masks of PrefetchingSampler::prefetchMany.
constexpr unsigned slotBit(BounceDim slot) {
    return 1u << int(slot);
}

/// A sampler that computes the numbers of many paths' bounces together, ahead of their use
/// (PathIntegrator::traceMany): prefetchMany(n, samplers, depths, slots) computes, for each
/// i < n, the numbers of bounce depths[i] in the slots of mask slots[i] (slotBit()s) of
/// *samplers[i], exactly as bounce1D / bounce2D would.
template <class S>
concept PrefetchingSampler = PathSampler<S> &&
    requires(std::size_t n, S* const* samplers, const int* depths, const unsigned* slots) {
    S::prefetchMany(n, samplers, depths, slots);
};

}  // namespace glint::render
