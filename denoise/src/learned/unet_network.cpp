// The U-Net of Open Image Denoise's RT filter, run with oneDNN.
//
// Graph (OIDN 2.x UNetFilter and training/model.py; every convolution is 3×3, stride 1, zero
// padding 1, followed by ReLU):
//
//   base/small  enc_conv0, enc_conv1, pool | enc_conv2, pool | enc_conv3, pool | enc_conv4, pool
//   large       enc_conv1a, enc_conv1b, pool | enc_conv{2,3,4}{a,b}, pool
//   then        enc_conv5a, enc_conv5b, up | dec_conv4a(concat pool3), dec_conv4b, up |
//               dec_conv3a(concat pool2), dec_conv3b, up | dec_conv2a(concat pool1), dec_conv2b,
//               up | dec_conv1a(concat input), dec_conv1b, dec_conv0 (large: dec_conv1c)
//
// pool is a 2×2 max pool with stride 2, up a nearest-neighbour 2× upsampling. The final ReLU is
// harmless: the output process clamps at 0 anyway. A convolution of a concatenation [a, b] is run
// as two convolutions into one destination, conv(a, W_a) then conv(b, W_b) + bias with oneDNN's
// sum post-op and the ReLU fused, so no concatenated tensor is ever stored.
//
// Memory formats are chosen by oneDNN (format_tag::any; nhwc with brgconv on AVX-512);
// primitives and reordered weights are built once per tile size (a Plan) and reused. Activations
// have fixed offsets in one arena (packed by lifetime) that the caller's UNetWorkspace holds, and
// so does the primitives' scratchpad: a plan built on one thread runs on others (the studio starts
// a thread per job), and oneDNN's own scratchpad belongs to the thread that created the primitive
// (executing it on another reads that thread's scratchpad, or freed memory: oneDNN's scratchpad
// guide, DNNL_ENABLE_CONCURRENT_EXEC off as Debian builds it).
#include "learned/unet_network.h"

#include <omp.h>
#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <new>
#include <oneapi/dnnl/dnnl.hpp>
#include <optional>

#include "glint/image/error.h"

namespace glint::denoise::learned {

using dnnl::memory;

namespace {

const dnnl::engine& cpuEngine() {
    static const dnnl::engine engine(dnnl::engine::kind::cpu, 0);
    return engine;
}

enum class OpKind { Conv, Pool, Up };

// One node of the graph: a convolution (of one source, or of the concatenation of two), a pool
// or an upsampling. Tensor 0 is the network input.
struct Op {
    OpKind kind = OpKind::Conv;
    int layer = -1;  // index into the network's layers (Conv only)
    int src0 = -1, src1 = -1, dst = -1;
};

struct TensorInfo {
    int channels = 0;
    int level = 0;  // resolution is the tile's divided by 2^level
};

struct Graph {
    std::vector<TensorInfo> tensors;
    std::vector<Op> ops;
};

memory::desc anyDesc(int c, int h, int w) {
    return {{1, c, h, w}, memory::data_type::f32, memory::format_tag::any};
}

// Attributes of a primitive whose scratchpad the caller passes at execution (DNNL_ARG_SCRATCHPAD).
dnnl::primitive_attr userScratchpad() {
    dnnl::primitive_attr attr;
    attr.set_scratchpad_mode(dnnl::scratchpad_mode::user);
    return attr;
}

// Offsets of buffers in one arena such that buffers whose lifetimes [first, last] (in steps)
// overlap do not share bytes: largest first, each at the lowest 4 KiB-aligned gap between the
// already placed buffers it overlaps (the greedy-by-size planner of TensorFlow Lite's arena,
// Pisarchyk and Lee 2020). `bytes` receives the arena's size.
std::vector<std::size_t> packArena(const std::vector<std::size_t>& sizes,
                                   const std::vector<int>& first, const std::vector<int>& last,
                                   std::size_t& bytes) {
    constexpr std::size_t kAlign = 4096;
    const std::size_t n = sizes.size();
    auto aligned = [&](std::size_t i) { return (sizes[i] + kAlign - 1) / kAlign * kAlign; };
    std::vector<std::size_t> order(n), offsets(n, 0);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
    std::vector<std::size_t> placed;
    bytes = 0;
    for (std::size_t b : order) {
        if (sizes[b] == 0) continue;
        std::vector<std::size_t> conflicts;
        for (std::size_t a : placed)
            if (first[a] <= last[b] && first[b] <= last[a]) conflicts.push_back(a);
        std::sort(conflicts.begin(), conflicts.end(),
                  [&](std::size_t x, std::size_t y) { return offsets[x] < offsets[y]; });
        std::size_t at = 0;
        for (std::size_t a : conflicts) {
            if (offsets[a] >= at + aligned(b)) break;
            at = std::max(at, offsets[a] + aligned(a));
        }
        offsets[b] = at;
        bytes = std::max(bytes, at + aligned(b));
        placed.push_back(b);
    }
    return offsets;
}

}  // namespace

void UNetWorkspace::Free::operator()(std::byte* p) const {
    std::free(p);
}

std::byte* UNetWorkspace::reserve(std::size_t bytes) {
    if (bytes <= m_size) return m_data.get();
    constexpr std::size_t kHuge = std::size_t(2) << 20;
    const std::size_t size = (bytes + kHuge - 1) / kHuge * kHuge;
    m_data.reset();
    void* p = std::aligned_alloc(kHuge, size);
    if (!p) throw std::bad_alloc();
    // Transparent huge pages where the kernel offers them: 512× fewer page faults.
    madvise(p, size, MADV_HUGEPAGE);
    m_data.reset(static_cast<std::byte*>(p));
    m_size = size;
    return m_data.get();
}

struct UNetNetwork::Layer {
    std::string name;
    int out = 0, in = 0;
    std::vector<float> weights;  // oihw
    std::vector<float> bias;
};

// The graph of a variant, with the layer names in order; layer channel counts are filled in from
// the weights by the constructor.
namespace {

struct GraphBuilder {
    Graph g;
    std::vector<std::string> names;

    int tensor(int level) {
        g.tensors.push_back({0, level});
        return int(g.tensors.size()) - 1;
    }
    int conv(const std::string& name, int a, int b = -1) {
        names.push_back(name);
        const int d = tensor(g.tensors[std::size_t(a)].level);
        g.ops.push_back({OpKind::Conv, int(names.size()) - 1, a, b, d});
        return d;
    }
    int pool(int a) {
        const int d = tensor(g.tensors[std::size_t(a)].level + 1);
        g.ops.push_back({OpKind::Pool, -1, a, -1, d});
        return d;
    }
    int up(int a) {
        const int d = tensor(g.tensors[std::size_t(a)].level - 1);
        g.ops.push_back({OpKind::Up, -1, a, -1, d});
        return d;
    }
};

GraphBuilder buildGraph(bool large) {
    GraphBuilder b;
    const int in = b.tensor(0);
    int p[5] = {in, -1, -1, -1, -1};
    if (large) {
        p[1] = b.pool(b.conv("enc_conv1b", b.conv("enc_conv1a", in)));
        for (int k = 2; k <= 4; ++k) {
            const std::string s = "enc_conv" + std::to_string(k);
            p[k] = b.pool(b.conv(s + "b", b.conv(s + "a", p[k - 1])));
        }
    } else {
        p[1] = b.pool(b.conv("enc_conv1", b.conv("enc_conv0", in)));
        for (int k = 2; k <= 4; ++k)
            p[k] = b.pool(b.conv("enc_conv" + std::to_string(k), p[k - 1]));
    }
    int x = b.up(b.conv("enc_conv5b", b.conv("enc_conv5a", p[4])));
    for (int k = 4; k >= 1; --k) {
        const std::string s = "dec_conv" + std::to_string(k);
        x = b.conv(s + "b", b.conv(s + "a", x, p[k - 1]));
        if (k > 1) x = b.up(x);
    }
    b.conv(large ? "dec_conv1c" : "dec_conv0", x);
    return b;
}

}  // namespace

// oneDNN primitives and reordered weights for one tile size.
struct UNetNetwork::Plan {
    struct Step {
        OpKind kind = OpKind::Conv;
        int src0 = -1, src1 = -1, dst = -1;
        dnnl::primitive main;   // conv (of src1 with bias when split), pool or resampling
        dnnl::primitive first;  // split conv: conv of src0 without bias
        memory weights, bias, weightsFirst;
        memory::desc mainScratch, firstScratch;  // their scratchpads (at scratchOffset)
    };
    Graph graph;
    std::vector<memory::desc> descs;
    std::vector<Step> steps;
    std::vector<std::size_t> offsets;  // of each tensor in the arena
    memory::desc inUser, outUser;
    // Reorders between the interleaved buffers and oneDNN's formats, only where they differ.
    std::optional<dnnl::reorder> inReorder, outReorder;
    memory::desc inScratch, outScratch;
    std::size_t arenaBytes = 0;  // of the activations
    // The scratchpad every primitive uses in turn: after the activations in the workspace.
    std::size_t scratchOffset = 0, scratchBytes = 0;
};

UNetNetwork::UNetNetwork(const TzaTensors& tensors, int inputChannels, const std::string& file)
    : m_inputChannels(inputChannels) {
    // Tell the variants apart as OIDN does: only the large net has enc_conv1b.
    const bool large = tensors.count("enc_conv1b.weight") > 0;
    GraphBuilder b = buildGraph(large);
    auto bad = [&](const std::string& what) {
        throw Error(ErrorKind::Format, "weights do not fit OIDN's U-Net: " + what, file);
    };
    if (tensors.size() != 2 * b.names.size())
        bad(std::to_string(tensors.size()) + " tensors, the " + (large ? "large" : "base") +
            " U-Net has " + std::to_string(2 * b.names.size()));
    // Check each layer's shape against its sources and propagate channel counts.
    b.g.tensors[0].channels = inputChannels;
    for (const Op& op : b.g.ops) {
        auto& dst = b.g.tensors[std::size_t(op.dst)];
        const auto& s0 = b.g.tensors[std::size_t(op.src0)];
        if (op.kind != OpKind::Conv) {
            dst.channels = s0.channels;
            continue;
        }
        const std::string& name = b.names[std::size_t(op.layer)];
        auto w = tensors.find(name + ".weight");
        auto bi = tensors.find(name + ".bias");
        if (w == tensors.end() || bi == tensors.end()) bad("missing tensor for layer " + name);
        const int in =
            s0.channels + (op.src1 >= 0 ? b.g.tensors[std::size_t(op.src1)].channels : 0);
        const auto& ws = w->second.shape;
        if (w->second.layout != "oihw" || ws.size() != 4 || ws[1] != in || ws[2] != 3 || ws[3] != 3)
            bad(name + ".weight is not [out, " + std::to_string(in) + ", 3, 3] oihw");
        if (bi->second.shape.size() != 1 || bi->second.shape[0] != ws[0])
            bad(name + ".bias does not have " + std::to_string(ws[0]) + " values");
        dst.channels = ws[0];
        m_layers.push_back({name, ws[0], in, w->second.data, bi->second.data});
    }
    if (b.g.tensors.back().channels != 3) bad("the last layer does not output 3 channels");
    m_variant = large ? "large" : (m_layers[2].out == 32 ? "small" : "base");
}

UNetNetwork::~UNetNetwork() = default;

int UNetNetwork::overlap() const {
    // OIDN: round_up(receptive field / 2, alignment) with receptive fields 174 and 202.
    const int field = m_variant == "large" ? 202 : 174;
    return (field / 2 + kUNetAlignment - 1) / kUNetAlignment * kUNetAlignment;
}

double UNetNetwork::macsPerPixel() const {
    const GraphBuilder b = buildGraph(m_variant == "large");
    double macs = 0.0;
    for (const Op& op : b.g.ops)
        if (op.kind == OpKind::Conv) {
            const Layer& l = m_layers[std::size_t(op.layer)];
            const int level = b.g.tensors[std::size_t(op.dst)].level;
            macs += double(l.out) * l.in * 9.0 / double(1 << (2 * level));
        }
    return macs;
}

double UNetNetwork::bytesPerPixel() const {
    constexpr int kSide = 256;
    return double(plan(kSide, kSide)->arenaBytes) / double(kSide * kSide);
}

std::shared_ptr<const UNetNetwork::Plan> UNetNetwork::plan(int h, int w) const {
    std::lock_guard lock(m_mutex);
    for (const auto& [size, p] : m_plans)
        if (size == std::make_pair(h, w)) return p;

    const auto& eng = cpuEngine();
    auto p = std::make_shared<Plan>();
    p->graph = buildGraph(m_variant == "large").g;
    Graph& g = p->graph;
    g.tensors[0].channels = m_inputChannels;
    p->descs.resize(g.tensors.size());
    auto reorderWeights = [&](const std::vector<float>& src, const memory::desc& user,
                              const memory::desc& want) {
        memory from(user, eng, const_cast<float*>(src.data()));
        memory to(want, eng);
        dnnl::stream s(eng);
        dnnl::reorder(from, to).execute(s, from, to);
        s.wait();
        return to;
    };
    const memory::dims strides{1, 1}, pad{1, 1};
    for (const Op& op : g.ops) {
        Plan::Step st;
        st.kind = op.kind;
        st.src0 = op.src0;
        st.src1 = op.src1;
        st.dst = op.dst;
        TensorInfo& dt = g.tensors[std::size_t(op.dst)];
        dt.channels = op.kind == OpKind::Conv ? m_layers[std::size_t(op.layer)].out
                                              : g.tensors[std::size_t(op.src0)].channels;
        const int dc = dt.channels, dh = h >> dt.level, dw = w >> dt.level;
        if (op.kind == OpKind::Conv) {
            const Layer& l = m_layers[std::size_t(op.layer)];
            // A split convolution reads its two sources with the two column blocks of W.
            const int c0 = g.tensors[std::size_t(op.src0)].channels;
            const bool split = op.src1 >= 0;
            const int cMain = split ? l.in - c0 : l.in;
            const int srcMain = split ? op.src1 : op.src0;
            auto srcDesc = [&](int t, int c) {
                const memory::desc& d = p->descs[std::size_t(t)];
                return d.is_zero() ? anyDesc(c, dh, dw) : d;
            };
            const memory::desc wMain({l.out, cMain, 3, 3}, memory::data_type::f32,
                                     memory::format_tag::any);
            const memory::desc bDesc({l.out}, memory::data_type::f32, memory::format_tag::x);
            dnnl::post_ops po;
            if (split) po.append_sum(1.0f);
            po.append_eltwise(1.0f, dnnl::algorithm::eltwise_relu, 0.0f, 0.0f);
            dnnl::primitive_attr attr = userScratchpad();
            attr.set_post_ops(po);
            const dnnl::convolution_forward::desc cd(
                dnnl::prop_kind::forward_inference, dnnl::algorithm::convolution_direct,
                srcDesc(srcMain, cMain), wMain, bDesc, anyDesc(l.out, dh, dw), strides, pad, pad);
            const dnnl::convolution_forward::primitive_desc pd(cd, attr, eng);
            if (p->descs[std::size_t(srcMain)].is_zero())
                p->descs[std::size_t(srcMain)] = pd.src_desc();
            p->descs[std::size_t(op.dst)] = pd.dst_desc();
            // Weights: the column block [c0, in) for a split convolution, all columns otherwise.
            std::vector<float> wm(std::size_t(l.out) * cMain * 9);
            const int cOff = split ? c0 : 0;
            for (int o = 0; o < l.out; ++o)
                std::copy_n(l.weights.begin() + (std::ptrdiff_t(o) * l.in + cOff) * 9, cMain * 9,
                            wm.begin() + std::ptrdiff_t(o) * cMain * 9);
            const memory::desc wUser({l.out, cMain, 3, 3}, memory::data_type::f32,
                                     memory::format_tag::oihw);
            st.weights = reorderWeights(wm, wUser, pd.weights_desc());
            st.bias = memory(bDesc, eng);
            std::copy(l.bias.begin(), l.bias.end(), static_cast<float*>(st.bias.get_data_handle()));
            st.main = dnnl::convolution_forward(pd);
            st.mainScratch = pd.scratchpad_desc();
            if (split) {
                const memory::desc wFirst({l.out, c0, 3, 3}, memory::data_type::f32,
                                          memory::format_tag::any);
                const dnnl::convolution_forward::desc fd(
                    dnnl::prop_kind::forward_inference, dnnl::algorithm::convolution_direct,
                    srcDesc(op.src0, c0), wFirst, pd.dst_desc(), strides, pad, pad);
                const dnnl::convolution_forward::primitive_desc fpd(fd, userScratchpad(), eng);
                GLINT_CHECK(fpd.dst_desc() == pd.dst_desc(), "split convolution formats differ");
                std::vector<float> wf(std::size_t(l.out) * c0 * 9);
                for (int o = 0; o < l.out; ++o)
                    std::copy_n(l.weights.begin() + std::ptrdiff_t(o) * l.in * 9, c0 * 9,
                                wf.begin() + std::ptrdiff_t(o) * c0 * 9);
                const memory::desc wfUser({l.out, c0, 3, 3}, memory::data_type::f32,
                                          memory::format_tag::oihw);
                st.weightsFirst = reorderWeights(wf, wfUser, fpd.weights_desc());
                st.first = dnnl::convolution_forward(fpd);
                st.firstScratch = fpd.scratchpad_desc();
            }
        } else if (op.kind == OpKind::Pool) {
            const dnnl::pooling_forward::desc pdsc(
                dnnl::prop_kind::forward_inference, dnnl::algorithm::pooling_max,
                p->descs[std::size_t(op.src0)], anyDesc(dc, dh, dw), {2, 2}, {2, 2}, {0, 0},
                {0, 0});
            const dnnl::pooling_forward::primitive_desc pd(pdsc, userScratchpad(), eng);
            p->descs[std::size_t(op.dst)] = pd.dst_desc();
            st.main = dnnl::pooling_forward(pd);
            st.mainScratch = pd.scratchpad_desc();
        } else {
            const dnnl::resampling_forward::desc rd(
                dnnl::prop_kind::forward_inference, dnnl::algorithm::resampling_nearest,
                p->descs[std::size_t(op.src0)], anyDesc(dc, dh, dw));
            const dnnl::resampling_forward::primitive_desc pd(rd, userScratchpad(), eng);
            p->descs[std::size_t(op.dst)] = pd.dst_desc();
            st.main = dnnl::resampling_forward(pd);
            st.mainScratch = pd.scratchpad_desc();
        }
        p->steps.push_back(std::move(st));
    }
    // Input and output reorders between interleaved (nhwc) buffers and oneDNN's formats.
    p->inUser =
        memory::desc({1, m_inputChannels, h, w}, memory::data_type::f32, memory::format_tag::nhwc);
    p->outUser = memory::desc({1, 3, h, w}, memory::data_type::f32, memory::format_tag::nhwc);
    if (p->descs[0] != p->inUser) {
        const dnnl::reorder::primitive_desc pd(eng, p->inUser, eng, p->descs[0], userScratchpad());
        p->inReorder = dnnl::reorder(pd);
        p->inScratch = pd.scratchpad_desc();
    }
    if (p->descs.back() != p->outUser) {
        const dnnl::reorder::primitive_desc pd(eng, p->descs.back(), eng, p->outUser,
                                               userScratchpad());
        p->outReorder = dnnl::reorder(pd);
        p->outScratch = pd.scratchpad_desc();
    }
    // Lifetimes: a tensor lives from its producing step to its last use (the input from before
    // the first step, the output until the output reorder).
    const int n = int(g.tensors.size());
    std::vector<int> first(std::size_t(n), -1), last(std::size_t(n), -1);
    for (std::size_t i = 0; i < p->steps.size(); ++i) {
        first[std::size_t(p->steps[i].dst)] = int(i);
        last[std::size_t(p->steps[i].src0)] = int(i);
        if (p->steps[i].src1 >= 0) last[std::size_t(p->steps[i].src1)] = int(i);
    }
    last.back() = int(p->steps.size());
    std::vector<std::size_t> sizes(static_cast<std::size_t>(n));
    for (int t = 0; t < n; ++t) sizes[std::size_t(t)] = p->descs[std::size_t(t)].get_size();
    p->offsets = packArena(sizes, first, last, p->arenaBytes);
    // One scratchpad, as large as the largest primitive's, after the activations (4 KiB-aligned,
    // as packArena leaves the arena's size).
    p->scratchOffset = p->arenaBytes;
    for (const memory::desc& d : {p->inScratch, p->outScratch})
        p->scratchBytes = std::max(p->scratchBytes, d.get_size());
    for (const Plan::Step& st : p->steps)
        p->scratchBytes =
            std::max({p->scratchBytes, st.mainScratch.get_size(), st.firstScratch.get_size()});
    // Keep a few plans (tiles of a frame have at most four sizes).
    constexpr std::size_t kMaxPlans = 6;
    if (m_plans.size() >= kMaxPlans) m_plans.erase(m_plans.begin());
    m_plans.emplace_back(std::make_pair(h, w), p);
    return p;
}

void UNetNetwork::run(int h, int w, const FillFn& fill, const ReadFn& read, int threads,
                      UNetWorkspace& workspace, const LayerFn& afterLayer) const {
    GLINT_CHECK(h > 0 && w > 0 && h % kUNetAlignment == 0 && w % kUNetAlignment == 0,
                "U-Net tile sizes must be positive multiples of 16");
    const std::shared_ptr<const Plan> p = plan(h, w);
    const auto& eng = cpuEngine();
    omp_set_num_threads(std::max(1, threads));
    dnnl::stream s(eng);

    // Every activation at its place in the arena, then the scratchpad.
    std::byte* arena = workspace.reserve(p->scratchOffset + p->scratchBytes);
    std::vector<memory> mem(p->descs.size());
    for (std::size_t t = 0; t < mem.size(); ++t)
        mem[t] = memory(p->descs[t], eng, arena + p->offsets[t]);
    auto scratch = [&](const memory::desc& d) { return memory(d, eng, arena + p->scratchOffset); };
    // The input, written in place when oneDNN reads it interleaved (no copy).
    if (p->inReorder) {
        const auto staged = std::make_unique_for_overwrite<float[]>(p->inUser.get_size() / 4);
        fill(staged.get());
        memory inUser(p->inUser, eng, staged.get());
        p->inReorder->execute(s, {{DNNL_ARG_FROM, inUser},
                                  {DNNL_ARG_TO, mem[0]},
                                  {DNNL_ARG_SCRATCHPAD, scratch(p->inScratch)}});
        s.wait();
    } else {
        fill(static_cast<float*>(mem[0].get_data_handle()));
    }
    const int totalConvs = int(m_layers.size());
    int convs = 0;
    for (const Plan::Step& st : p->steps) {
        const memory& dst = mem[std::size_t(st.dst)];
        if (st.kind == OpKind::Conv) {
            const bool split = st.src1 >= 0;
            if (split)
                st.first.execute(s, {{DNNL_ARG_SRC, mem[std::size_t(st.src0)]},
                                     {DNNL_ARG_WEIGHTS, st.weightsFirst},
                                     {DNNL_ARG_DST, dst},
                                     {DNNL_ARG_SCRATCHPAD, scratch(st.firstScratch)}});
            st.main.execute(s, {{DNNL_ARG_SRC, mem[std::size_t(split ? st.src1 : st.src0)]},
                                {DNNL_ARG_WEIGHTS, st.weights},
                                {DNNL_ARG_BIAS, st.bias},
                                {DNNL_ARG_DST, dst},
                                {DNNL_ARG_SCRATCHPAD, scratch(st.mainScratch)}});
        } else {
            st.main.execute(s, {{DNNL_ARG_SRC, mem[std::size_t(st.src0)]},
                                {DNNL_ARG_DST, dst},
                                {DNNL_ARG_SCRATCHPAD, scratch(st.mainScratch)}});
        }
        s.wait();
        if (st.kind == OpKind::Conv && afterLayer) afterLayer(++convs, totalConvs);
    }
    // The output, read in place when oneDNN wrote it interleaved.
    if (p->outReorder) {
        const auto staged = std::make_unique_for_overwrite<float[]>(p->outUser.get_size() / 4);
        memory outUser(p->outUser, eng, staged.get());
        p->outReorder->execute(s, {{DNNL_ARG_FROM, mem.back()},
                                   {DNNL_ARG_TO, outUser},
                                   {DNNL_ARG_SCRATCHPAD, scratch(p->outScratch)}});
        s.wait();
        read(staged.get());
    } else {
        read(static_cast<const float*>(mem.back().get_data_handle()));
    }
}

}  // namespace glint::denoise::learned
