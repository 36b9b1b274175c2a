// identity — the render as it is: no filtering.
//
// Every finite pixel comes out as it went in, bit for bit. It is auto's candidate for the pixels
// that no filter improves: where the render has converged (a long render, a region the samples
// went to) every smoothing member only adds its bias, and without this member auto had to pick
// one of them (docs/auto.md, "The render itself is a candidate"). In a painting session it is the
// layer that brings the render back where a stroke went too far.
//
// A missing pixel (a NaN or an Inf in any channel) follows Glint's policy: its output is the
// average of its finite 8-neighbours (0 when none is), so the output is finite everywhere and the
// filter reads one pixel beyond a region.
//
// Parameters: none.
#include <cstddef>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "filters/factories.h"
#include "filters/filter_util.h"

namespace glint::denoise {

namespace {

constexpr std::string_view kDescription =
    "identity: the render as it is, no filtering (auto's candidate where no filter improves the "
    "render); a missing (NaN/Inf) pixel becomes the average of its finite 8-neighbours.";

class IdentityFilter final : public Filter {
  public:
    std::string_view name() const override { return "identity"; }
    std::string_view description() const override { return kDescription; }
    const std::vector<ParamSpec>& params() const override { return m_params; }
    FilterTraits traits() const override {
        FilterTraits t;
        t.smooths = false;
        return t;
    }
    int margin(const ParamValues& /*params*/) const override { return 1; }

    Image apply(const FrameBuffers& frame, const ParamValues& /*params*/, const Rect& roi,
                WorkContext& work) const override {
        const Image& in = frame.color();
        Image out(roi.width(), roi.height(), 3);
        work.expectWork(roi.height());
        work.parallelFor(roi.y0, roi.y1, [&](int y) {
            for (int x = roi.x0; x < roi.x1; ++x) {
                float* o = &out(x - roi.x0, y - roi.y0, 0);
                const float* p = in.row(y) + std::size_t(x) * 3;
                if (detail::isFinitePixel(p, 3)) {
                    for (int c = 0; c < 3; ++c) o[c] = p[c];
                    continue;
                }
                double sum[3] = {0.0, 0.0, 0.0};
                int n = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= in.width() ||
                            ny >= in.height())
                            continue;
                        const float* q = in.row(ny) + std::size_t(nx) * 3;
                        if (!detail::isFinitePixel(q, 3)) continue;
                        for (int c = 0; c < 3; ++c) sum[c] += double(q[c]);
                        ++n;
                    }
                for (int c = 0; c < 3; ++c) o[c] = n > 0 ? float(sum[c] / double(n)) : 0.0f;
            }
        });
        return out;
    }

    /// Every output is its input: ∂out/∂in = 1.
    std::optional<Image> divergence(const FrameBuffers& /*frame*/, const ParamValues& /*params*/,
                                    const Rect& roi) const override {
        return Image(roi.width(), roi.height(), 3, 1.0f);
    }

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace

std::unique_ptr<Filter> makeIdentityFilter() {
    return std::make_unique<IdentityFilter>();
}

}  // namespace glint::denoise
