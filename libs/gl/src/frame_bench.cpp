// Frame-time benchmark of the techniques: fill view plus distances, interleaved rounds.
#include "leanfade/gl/detail/frame_bench.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/figure.hpp"

namespace leanfade::gl {
namespace {

constexpr float kFillDistance = 3.0f;  // bounding radii
constexpr float kMinFillFov = 1.5f;    // degrees
constexpr float kFillFovStep = 0.8f;
constexpr int kProbeHeight = 96;  // pixels of the fill view's coverage probe
constexpr int kMaxBenchSize = 8192;

// An RGBA8 colour texture and a 24-bit depth renderbuffer: a window's back buffer, offscreen.
struct BenchTarget {
    int width = 0, height = 0;
    Texture color;
    Renderbuffer depth;
    Framebuffer framebuffer;

    BenchTarget(int w, int h) : width(w), height(h) {
        color = create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(color.get(), 1, GL_RGBA8, w, h);
        depth = create_renderbuffer();
        glNamedRenderbufferStorage(depth.get(), GL_DEPTH_COMPONENT24, w, h);
        framebuffer = create_framebuffer();
        glNamedFramebufferTexture(framebuffer.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
        glNamedFramebufferRenderbuffer(framebuffer.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                       depth.get());
        const GLenum status = glCheckNamedFramebufferStatus(framebuffer.get(), GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            throw Error("bench", "the RGBA8 + depth24 framebuffer is incomplete");
    }

    void clear() const {
        const float black[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        const float far_depth = 1.0f;
        glClearNamedFramebufferfv(framebuffer.get(), GL_COLOR, 0, black);
        glClearNamedFramebufferfv(framebuffer.get(), GL_DEPTH, 0, &far_depth);
    }

    // Fraction of pixels written (alpha 1; cleared to alpha 0).
    double covered_fraction() const {
        std::vector<std::uint8_t> rgba(std::size_t(width) * std::size_t(height) * 4);
        glGetTextureImage(color.get(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()),
                          rgba.data());
        std::size_t covered = 0;
        for (std::size_t i = 3; i < rgba.size(); i += 4) covered += rgba[i] != 0;
        return double(covered) / double(std::size_t(width) * std::size_t(height));
    }
};

RenderRequest frame_request(const FrameBenchRequest& r, Technique technique, const View& view,
                            int width, int height) {
    RenderRequest request;
    request.technique = technique;
    request.width = width;
    request.height = height;
    request.view = view;
    request.settings = r.settings;
    return request;
}

// The bench's view at a distance, or the fill view; one entry per measured view.
struct PlannedView {
    std::string name;
    float distance;
    bool fill;
};

ViewResult run_view(Renderer& renderer, const FrameBenchRequest& r, const PlannedView& planned,
                    IntervalTimer& timer, BenchTarget& target) {
    ViewResult result;
    result.name = planned.name;
    const float aspect = float(r.width) / float(r.height);
    View view;
    if (planned.fill) {
        view = fill_view(renderer, aspect, r.view_direction);
    } else {
        view = view_at_distance(planned.distance, kDefaultFovYDegrees, r.view_direction);
    }
    result.distance = glm::length(view.eye - view.target);
    result.fov_y_degrees = view.fov_y_degrees;

    // Entries: the floor first, then the techniques, each with its draw call.
    struct Entry {
        std::string name;
        std::optional<VariantKey> variant;  // none: the technique's own
        Technique technique;
    };
    std::vector<Entry> entries;
    if (r.floor)
        entries.push_back({kFloorName, VariantKey::constant_color(), Technique::Lean});
    for (Technique t : r.techniques) entries.push_back({to_string(t), std::nullopt, t});
    const int count = int(entries.size());
    result.timings.resize(entries.size());
    for (std::size_t i = 0; i < entries.size(); ++i) {
        result.timings[i].name = entries[i].name;
        if (!entries[i].variant) result.timings[i].technique = entries[i].technique;
    }

    // Coverage of the full-size framebuffer, with the floor's program.
    target.clear();
    renderer.draw(frame_request(r, Technique::Lean, view, r.width, r.height),
                  target.framebuffer.get(), VariantKey::constant_color());
    result.coverage = target.covered_fraction();

    const int rounds = r.warmup + r.frames;
    for (int round = 0; round < rounds; ++round) {
        const bool timed = round >= r.warmup;
        std::vector<int> order(entries.size());
        for (int k = 0; k < count; ++k) order[std::size_t(k)] = (k + round) % count;
        for (int index : order) {
            const Entry& e = entries[std::size_t(index)];
            RenderRequest request = frame_request(r, e.technique, view, r.width, r.height);
            request.time = float(round) * r.seconds_per_round;
            if (timed) timer.begin();
            target.clear();
            renderer.draw(request, target.framebuffer.get(), e.variant);
            if (timed) timer.end();
        }
        if (!timed) continue;
        const std::vector<double> ms = timer.collect();
        for (std::size_t k = 0; k < order.size(); ++k)
            result.timings[std::size_t(order[k])].frame_ms.push_back(ms[k]);
        result.order.push_back(std::move(order));
    }
    for (TechniqueTiming& t : result.timings) {
        t.stats = sample_stats(t.frame_ms);
        t.fps = t.stats.median > 0.0 ? 1000.0 / t.stats.median : 0.0;
    }
    renderer.context().check("benchmarking " + planned.name);
    return result;
}

}  // namespace

const TechniqueTiming* ViewResult::find(const std::string& technique) const {
    for (const TechniqueTiming& t : timings)
        if (t.name == technique) return &t;
    return nullptr;
}

const TechniqueTiming* ViewResult::find(Technique technique) const {
    for (const TechniqueTiming& t : timings)
        if (t.technique == technique) return &t;
    return nullptr;
}

const TechniqueTiming* ViewResult::floor() const {
    for (const TechniqueTiming& t : timings)
        if (!t.technique) return &t;
    return nullptr;
}

namespace {

// Median over rounds of a[i] / b[i]; 0 when either is missing.
double median_ratio(const TechniqueTiming* ta, const TechniqueTiming* tb) {
    if (ta == nullptr || tb == nullptr || ta->frame_ms.size() != tb->frame_ms.size() ||
        ta->frame_ms.empty())
        return 0.0;
    std::vector<double> ratios;
    for (std::size_t i = 0; i < ta->frame_ms.size(); ++i)
        if (tb->frame_ms[i] > 0.0) ratios.push_back(ta->frame_ms[i] / tb->frame_ms[i]);
    std::sort(ratios.begin(), ratios.end());
    return sorted_quantile(ratios, 0.5);
}

}  // namespace

double ViewResult::ratio(Technique a, Technique b) const { return median_ratio(find(a), find(b)); }

double ViewResult::ratio_to_floor(Technique a) const { return median_ratio(find(a), floor()); }

const ViewResult* SceneResult::find(const std::string& view_name) const {
    for (const ViewResult& v : views)
        if (v.name == view_name) return &v;
    return nullptr;
}

void validate_frame_bench(const FrameBenchRequest& r) {
    if (r.width < 16 || r.height < 16 || r.width > kMaxBenchSize || r.height > kMaxBenchSize)
        throw Error::setting("size", "must be 16..8192 pixels on a side, got " +
                                         std::to_string(r.width) + "x" + std::to_string(r.height));
    if (r.techniques.empty() && !r.floor) throw Error::setting("techniques", "nothing to measure");
    for (Technique t : r.techniques)
        if (info(t).supersampled)
            throw Error::setting(
                "techniques", std::string("the ") + to_string(t) +
                                  " is an offline supersampled image, not a real-time technique; "
                                  "choose among " +
                                  technique_names(approximating_techniques()));
    if (r.frames < 1 || r.frames > 100000)
        throw Error::setting("frames", "must be in [1, 100000], got " + std::to_string(r.frames));
    if (r.warmup < 0 || r.warmup > 100000)
        throw Error::setting("warmup", "must be in [0, 100000], got " + std::to_string(r.warmup));
    if (!r.fill && r.distances.empty()) throw Error::setting("distances", "no view to measure");
    if (!(r.seconds_per_round >= 0.0f) || !std::isfinite(r.seconds_per_round))
        throw Error::setting("seconds-per-round", "must be a finite number of seconds >= 0");
    for (float d : r.distances)
        if (!(d > 1.0f) || !std::isfinite(d))
            throw Error::setting(
                "distances",
                "distances are in bounding radii and must be > 1, got " + std::to_string(d));
    leanfade::validate(r.settings);
}

View fill_view(Renderer& renderer, float aspect, glm::vec3 direction, double* coverage) {
    const int probe_height = kProbeHeight;
    const int probe_width = std::max(1, int(std::lround(float(probe_height) * aspect)));
    BenchTarget probe(probe_width, probe_height);
    View best;
    double best_coverage = -1.0;
    for (float fov = kDefaultFovYDegrees; fov >= kMinFillFov; fov *= kFillFovStep) {
        const View view = view_at_distance(kFillDistance, fov, direction);
        probe.clear();
        RenderRequest request;
        request.width = probe_width;
        request.height = probe_height;
        request.view = view;
        renderer.draw(request, probe.framebuffer.get(), VariantKey::constant_color());
        const double covered = probe.covered_fraction();
        if (covered > best_coverage) {
            best = view;
            best_coverage = covered;
        }
        if (covered >= 1.0) break;
    }
    if (coverage != nullptr) *coverage = best_coverage;
    return best;
}

FrameBenchResult run_frame_bench(Renderer& renderer, const std::vector<FrameBenchScene>& scenes,
                                 const FrameBenchRequest& request,
                                 const std::function<void(int done, int total)>& progress) {
    validate_frame_bench(request);
    if (scenes.empty()) throw Error::setting("scenes", "no scene to measure");
    for (const FrameBenchScene& s : scenes)
        if (s.mesh == nullptr && s.scene == nullptr)
            throw Error::setting("scenes", "scene '" + s.name + "' has no mesh");
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (request.width > max_size || request.height > max_size)
        throw Error::setting(
            "size", "larger than GL_MAX_RENDERBUFFER_SIZE (" + std::to_string(max_size) + ")");

    FrameBenchResult result;
    result.timing = choose_timing(request.timing, renderer.context());
    result.gl_renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    result.gl_version = reinterpret_cast<const char*>(glGetString(GL_VERSION));

    std::vector<PlannedView> views;
    if (request.fill) views.push_back({"fill", kFillDistance, true});
    for (float d : request.distances) {
        std::string name = "d";  // appended, not "d" + ...: GCC 12 warns (-Wrestrict) on that
        name += distance_text(d);
        views.push_back({name, d, false});
    }

    IntervalTimer timer(result.timing.method);
    BenchTarget target(request.width, request.height);
    const int total = int(scenes.size() * views.size());
    int done = 0;
    for (const FrameBenchScene& s : scenes) {
        SceneResult scene_result;
        scene_result.name = s.name;
        if (s.scene != nullptr) {
            renderer.set_scene(*s.scene);
            for (const scene::Object& o : s.scene->objects) {
                scene_result.triangles += o.mesh.triangle_count();
                scene_result.vertices += o.mesh.vertices.size();
            }
        } else {
            renderer.set_mesh(*s.mesh);
            scene_result.triangles = s.mesh->triangle_count();
            scene_result.vertices = s.mesh->vertices.size();
        }
        for (const PlannedView& planned : views) {
            scene_result.views.push_back(run_view(renderer, request, planned, timer, target));
            ++done;
            if (progress) progress(done, total);
        }
        result.scenes.push_back(std::move(scene_result));
    }
    return result;
}

}  // namespace leanfade::gl
