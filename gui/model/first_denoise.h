// A scene's first render is shown denoised, not raw: when a scene or an EXR is opened and its
// session starts with no layers, one layer (its filter's defaults, weight 1 everywhere) is added,
// as the user could do by hand. The filter is chosen by measurement: the learned filter (unet)
// when it runs here and the render has albedo and normal (the lab measured it best at the
// studio's spp on every scene, docs/lab/first-denoise.md), with its weights for clean features
// when the render's are (they keep the texture detail the albedo holds); else, on the render
// itself, each
// classical candidate's defaults are applied and their error estimated as auto estimates a
// member's (SURE from the variance, the halves, or the image-only noise estimate; no
// reference), and the smallest wins (cross-bilateral alone erased detail its guides do not
// see). It is an ordinary layer: one undo step, journalled, painted over or removed like any
// other. No widgets here.
#pragma once

#include <QObject>

#include <functional>
#include <string>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/image/frame_buffers.h"

namespace glint::studio {

class Document;
class SessionAdapter;

/// One candidate of the first denoise and its estimated error on the frame.
struct FirstDenoiseEstimate {
    std::string filter;
    double mse = 0.0;  ///< auto's estimate, mean over the measured region and channels
};

/// What the measurement chose and what it saw.
struct FirstDenoiseChoice {
    std::string filter;           ///< "" when no candidate can run (the render stays raw)
    denoise::ParamValues params;  ///< over the filter's defaults (empty: its defaults)
    std::vector<FirstDenoiseEstimate> estimates;  ///< in candidate order (empty: one candidate)
};

class FirstDenoise : public QObject {
    Q_OBJECT
  public:
    /// The classical filters tried, in the order of preference when estimates tie.
    static const std::vector<std::string>& classicalCandidates();
    /// The candidates on `frame`: the learned filter (model/learned_member.h) when it runs here
    /// and the frame has albedo and normal, then, when the frame has albedo, normal and depth
    /// (a render's guides; a colour-only EXR stays raw), the classical candidates it can run.
    static std::vector<std::string> candidatesFor(const FrameBuffers& frame);
    /// Measures `candidates` (registry names, at their defaults) on `frame` over a centred
    /// window of at most kMeasuredSide² pixels and picks the smallest estimated error (the
    /// first candidate when the frame cannot be estimated, e.g. non-finite values). Runs the
    /// filters: call it on a worker. Deterministic.
    static FirstDenoiseChoice choose(const FrameBuffers& frame,
                                     const std::vector<std::string>& candidates);
    /// What the studio adds: the learned filter when it is a candidate (the lab's measurement),
    /// with its weights for noise-free features (aux = clean) when featuresAreClean(frame), else
    /// choose(frame, candidatesFor(frame)).
    static FirstDenoiseChoice choose(const FrameBuffers& frame);
    /// Whether `frame`'s albedo and normal are clean enough for the learned filter's weights
    /// for noise-free features, which keep the texture detail the albedo holds (decals, printed
    /// lines) where its default weights for noisy features blur it: the means of the albedo's
    /// and the normal's variance-of-the-mean layers (finite pixels, every channel) are both at
    /// most kCleanFeatureVariance. False without those layers.
    static bool featuresAreClean(const FrameBuffers& frame);
    /// Between the renders whose features the lab found clean (at most 4.3e-4 at 16 spp) and
    /// those it found noisy (depth of field: 1.4e-3 and more; docs/lab/first-denoise.md).
    static constexpr double kCleanFeatureVariance = 1e-3;
    /// The side of the window the candidates are measured over.
    static constexpr int kMeasuredSide = 384;

    /// Watches `document` and `session`; `allowed()` is asked before a layer is added (false
    /// while a journal is restored, or when the user turned the default off).
    FirstDenoise(Document* document, SessionAdapter* session, std::function<bool()> allowed,
                 QObject* parent = nullptr);

  private:
    void onSessionReset();

    Document* m_document;
    SessionAdapter* m_session;
    std::function<bool()> m_allowed;
    bool m_armed = false;  // a file was opened and its first session has not started yet
};

}  // namespace glint::studio
