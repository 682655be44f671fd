#pragma once
// Offscreen renderer of one bump-mapped object with any technique of the technique table
// (leanfade/core/technique.hpp).
//
// Spaces and units:
// - World space is the mesh's object space moved so that its bounding-box centre is at the origin
//   and scaled so that its bounding radius (scene::Bounds::radius) is 1: world units are bounding
//   radii, for every scene. y is up.
// - Images are linear radiance (RGB float, not sRGB), row 0 at the top.
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/detail/generate.hpp"
#include "leanfade/gl/detail/objects.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::gl {

using leanfade::all_techniques;
using leanfade::parse_technique;
using leanfade::parse_techniques;
using leanfade::Technique;
using leanfade::to_string;

// What the fragment stage writes (debug output modes for measurements).
enum class OutputMode {
    Color,     // (Ka + Kd NdotL + Specular) * light, then fog
    Diffuse,   // (Ka + Kd NdotL) * light, no fog
    Specular,  // Ks NdotL^sf D F * light, no fog
    // (NdotL, d, 0): the inputs of specular fading from lean1 (lf_fade_terms), for calibration;
    // any technique (all read lean1), no fog, 0 where the object does not cover.
    FadeTerms,
};

// Vertical field of view of the figures: at 3 bounding radii the teapot (the widest built-in
// object relative to its bounding sphere) fills a square cell with a small margin.
inline constexpr float kDefaultFovYDegrees = 34.0f;

// A pinhole camera in world space.
struct View {
    glm::vec3 eye{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = kDefaultFovYDegrees;  // vertical field of view
    float near_plane = 0.1f;                    // world units
    float far_plane = 100.0f;                   // world units

    glm::mat4 view_matrix() const;                    // world -> eye
    glm::mat4 projection_matrix(float aspect) const;  // eye -> clip (OpenGL, depth -1..1)
};

// Default viewing direction of the figures: from the front (+z), slightly above.
using leanfade::kDefaultViewDirection;  // leanfade/core/detail/camera.hpp

// A camera looking at `target` (default: the world origin, the object's centre) from `distance`
// world units (object bounding radii, > 1) along `direction` (from the target toward the eye, any
// non-zero length), with near and far planes enclosing the unit bounding sphere. Looking straight
// up or down, the image's up is -z.
View view_at_distance(float distance, float fov_y_degrees = kDefaultFovYDegrees,
                      glm::vec3 direction = kDefaultViewDirection,
                      glm::vec3 target = glm::vec3(0.0f));

// Radius in pixels of the object's bounding sphere as seen by `view` in an image `height` pixels
// tall (the exact silhouette radius of a unit sphere at the view's distance).
float projected_radius_pixels(const View& view, int height);

struct RenderRequest {
    Technique technique = Technique::Lean;
    int width = 256;  // output pixels
    int height = 256;
    View view;
    ShadingSettings settings;  // mip_bias, anisotropy and msaa included
    OutputMode output = OutputMode::Color;
    int reference_samples = 8;   // k of the reference (k x k samples per pixel), 1..16
    glm::vec3 background{0.0f};  // linear RGB of pixels the object does not cover
    // Seconds since the start of the animation: a moving bump layer's texture coordinates are
    // offset by its velocity times `time` (scene::MaterialLayer::velocity). Finite.
    float time = 0.0f;
};

// The fragment program that draws `request`: for the colour output without fog, the technique's
// plain variant when there is one (the same image without the output and fog branches, which
// llvmpipe executes for every pixel; docs/perf.md); fading with its defaults while it is on, the
// fast variant (shader_library.hpp). `leanfade shaders` names it per technique in shaders.json.
VariantKey variant_for(const RenderRequest& request);

// The shading block of a draw with `settings` (what Renderer fills per object): the parameters
// (the base roughness left out when the map has it baked), the map's scale sc and encoding
// offset o (lean_offset(map.encoding): 1 for UNORM maps, 0 for the signed float maps), the output
// mode, fog, and no surface maps (`maps` = 0: the caller sets the bits of the maps it binds).
shading::LfShadingUniforms shading_uniforms(const ShadingSettings& settings, bool roughness_baked,
                                            float map_scale, float map_offset, OutputMode output);

// The LEAN texture as uploaded: a GL_TEXTURE_2D_ARRAY of 2 slices (lean1, lean2) with every MIP
// level of the map, rows flipped so that +v is up.
struct LeanTextureInfo {
    int width = 0;
    int height = 0;
    int levels = 0;
    Storage storage = Storage::Unorm16;
    float scale = 1.0f;            // sc, passed as a uniform
    float lean_offset = 1.0f;      // o of the map's encoding (lf_unpack), passed as a uniform
    bool roughness_baked = false;  // inv_s_shading = 0 when true
};

class Renderer {
  public:
    // The context must stay alive and current while the renderer is used.
    explicit Renderer(Context& context, ShaderSources sources = ShaderSources::embedded());
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Draws one mesh with one material (the frame's settings, the LEAN map of set_lean_map); its
    // model matrix maps it to the unit bounding sphere (see above). Throws
    // leanfade::Error(mesh.name, cause) for an empty mesh or one with a zero radius.
    void set_mesh(const scene::Mesh& mesh);
    // Uploads the two slices with all levels, as the one LEAN map of every material. Throws
    // leanfade::Error("LEAN map", cause) for a map without levels, inconsistent level sizes or
    // byte counts, or one larger than the GL limit.
    void set_lean_map(const PackedLeanMap& map);
    // Draws a scene of several objects and materials instead (scene::validate's errors, a glTF
    // material factor out of range: Error("scene", cause), set_lean_map's for each map); the model
    // matrix maps the scene to the unit bounding sphere. All or nothing: an error keeps the old.
    void set_scene(const scene::Scene& scene);

    // Renders one image (linear RGB, top row first). Requires a mesh and a LEAN map. Throws
    // leanfade::Error for invalid settings or sizes and for GL errors.
    Image render(const RenderRequest& request);

    // Renders like render() but keeps the result on the GPU, for interactive display: the linear
    // radiance is copied (glBlitNamedFramebuffer, nearest) into colour attachment 0 of
    // `framebuffer` (0 = the default framebuffer) with its lower-left corner at (x, y) in GL
    // window coordinates, request.width x request.height pixels. Nothing is read back.
    void render_to(const RenderRequest& request, GLuint framebuffer, int x = 0, int y = 0);

    // Draws the object once into `framebuffer` (0 = the default framebuffer), which the caller
    // owns and clears (colour and depth attachments, any sample count): the viewport is
    // (0, 0, request.width, request.height), the render state that of render(), and nothing is
    // cleared, resolved, checked or read back, so a frame costs what its shading costs (the
    // frame loop of `leanfade bench`). `variant` is another program with the same vertex stage
    // to draw with instead of the technique's: VariantKey::constant_color() is the
    // constant-colour fill-rate floor. Throws leanfade::Error without a mesh or map, for invalid
    // settings and for the reference (a multi-pass technique: render() only).
    void draw(const RenderRequest& request, GLuint framebuffer,
              std::optional<VariantKey> variant = std::nullopt);

    // Rebuilds every program built so far from the sources, all or nothing: on a compile or link
    // error it throws leanfade::Error (naming the file) and keeps the previous programs, so that
    // an interactive viewer goes on drawing with the last good shaders.
    void rebuild_shaders();

    // The map the "height" method generates for material `material` of the scene (bump layers
    // that move, tile differently or have per-texel weights: docs/math.md §6) at `time`
    // (seconds), read back in the CPU baker's layout (LeanGenerator::read_back). Throws
    // leanfade::Error("scene", cause) for another material.
    PackedLeanMap mixed_lean_map(int material, float time);

    const glm::mat4& model_matrix() const { return model_; }
    // The first LEAN map's texture (an empty description before any map).
    const LeanTextureInfo& lean_texture() const;
    Context& context() { return context_; }

  private:
    struct Target;
    GLuint program(const VariantKey& variant);
    // Draws every object with the program of `variant` (its kLayered twin for a material with
    // bump layers).
    void draw_scene(const VariantKey& variant, const RenderRequest& request,
                    const glm::mat4& clip);
    void render_reference(const RenderRequest& request, Target& output);
    // The LEAN texture's LOD bias and anisotropy from the settings.
    void apply_sampler_state(const ShadingSettings& settings);
    // Validates the request and renders it into target_ (kept while the size and samples stay).
    Target& render_target(const RenderRequest& request);

    Context& context_;
    ShaderSources sources_;
    std::map<VariantKey, Program> programs_;
    struct GpuObject {
        VertexArray vertex_array;
        Buffer vertices;
        Buffer indices;
        GLsizei index_count = 0;
        int material = 0;
        glm::mat4 transform{1.0f};
        glm::vec3 centre{0.0f};  // of the mesh's bounds, object space: blended objects' order
    };
    struct GpuMap {
        Texture texture;  // GL_TEXTURE_2D_ARRAY: slice 0 lean1, slice 1 lean2, every level
        LeanTextureInfo info;
    };
    // The textures of a material's bump layers besides their LEAN maps (in maps_).
    struct GpuLayers {
        Texture cross_terms;  // GL_TEXTURE_2D_ARRAY RGBA32F, a slice per pair, every level
        Texture weights;      // GL_TEXTURE_2D RGBA32F (t_0..t_3) with MIPs, when a weight map
        // The "height" method (docs/math.md §6): the mixed map, generated on the GPU for the
        // frame's time whenever it changes, drawn like a single LEAN map.
        std::unique_ptr<LeanGenerator> mixer;
        GenerateOptions mixed;          // its sc and storage
        std::optional<float> mixed_time;  // seconds: the time it was generated for, if it was
    };
    GpuLayers upload_layers(const scene::Scene& scene, const scene::Material& material);
    // Binds a layered material's maps, cross terms, weights and its LfLayerBlock for `time`.
    void bind_layers(const scene::Material& material, const GpuLayers& layers, float time);
    // Regenerates the mixed map of every "height" material whose time is not `time` (seconds).
    void update_mixed_layers(float time);
    GpuObject upload_object(const scene::Mesh& mesh, int material, const glm::mat4& transform);
    GpuMap upload_map(const PackedLeanMap& map);

    std::vector<GpuObject> objects_;
    std::vector<scene::Material> materials_;
    std::vector<GpuMap> maps_;
    std::vector<GpuLayers> material_layers_;  // per material (empty textures: single map)
    // Scene::maps: per kind of scene::kMapKinds, a GL_TEXTURE_2D per texture with its MIP chain.
    std::array<std::vector<Texture>, scene::kMapKindCount> surface_maps_;
    Texture white_;                      // 1x1 white: the base colour of the others
    glm::mat4 model_{1.0f};  // scene -> world: the unit bounding sphere
    VertexArray empty_vertex_array_;
    Buffer shading_block_;  // LfShadingUniforms, std140 (leanfade/gl/detail/shading_block.hpp)
    Buffer object_block_;   // LfObjectUniforms, std140
    Buffer layer_block_;    // LfLayerUniforms, std140 (layered materials)
    std::unique_ptr<Target> target_;
};

}  // namespace leanfade::gl
