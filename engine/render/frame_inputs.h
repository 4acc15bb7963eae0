#pragma once
// What the renderer needs from the scene each frame, besides the Gaussian records.
#include <array>
#include <vector>

#include "core/math.h"
#include "core/names.h"
#include "gpu_types.h"

namespace pbdsplat::render {

struct Camera {
    Vec3f eye{0.0f, 0.0f, 3.0f};
    Vec3f target{0.0f, 0.0f, 0.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = 45.0f;
    float z_near = 0.05f;
    float z_far = 100.0f;
};

// How the environment map is looked up (paper sections 5.6.2 and 7.2): from the world position
// relative to the body's centre (the paper's), from the normal, or the normal for the diffuse
// term and the position for the specular one. `off` leaves the flat ambient term.
enum class EnvSampling { off, position, normal, hybrid };
inline constexpr core::EnumName<EnvSampling> k_env_sampling_names[] = {
    {EnvSampling::position, "position"}, {EnvSampling::normal, "normal"}, {EnvSampling::hybrid, "hybrid"}, {EnvSampling::off, "off"}};
inline const char* env_sampling_name(EnvSampling s) { return core::name_of<EnvSampling>(k_env_sampling_names, s); }
inline std::optional<EnvSampling> env_sampling_from_name(std::string_view n) {
    return core::from_name<EnvSampling>(k_env_sampling_names, n);
}

struct Environment {
    EnvSampling sampling = EnvSampling::position;
    float diffuse = 1.0f;    // k_d of eq. 24
    float specular = 1.0f;   // scales the material's specular strength for the reflection
    float intensity = 1.0f;  // of the whole map
    Vec3f center = Vec3f::Zero();  // the body's centre, updated every frame by the scene
    // With several models, each one's centre (the record's model picks it, gpu_types.h): a model
    // is lit from its own, so another one moving does not relight it. Empty: `center` for all.
    std::vector<Vec3f> model_centers;
};

enum class LightType { directional, point, spot };

// Direct lights besides the key light (eq. 25): at most k_max_lights of them.
inline constexpr size_t k_max_lights = PBDSPLAT_MAX_LIGHTS;
struct Light {
    LightType type = LightType::point;
    Vec3f position = Vec3f(0.0f, 2.0f, 2.0f);   // point, spot
    Vec3f direction = Vec3f(0.0f, -1.0f, 0.0f);  // spot axis (away from the light); directional: towards the light
    Vec3f color{1.0f, 1.0f, 1.0f};
    float intensity = 1.0f;
    float range = 10.0f;  // point and spot: no light beyond
    float inner_degrees = 15.0f, outer_degrees = 25.0f;  // spot cone
};

struct Lighting {
    Vec3f direction{0.4f, 0.7f, 0.6f};  // from the surface towards the light; normalised on use
    Vec3f color{1.0f, 1.0f, 1.0f};
    float intensity = 1.0f;
    Vec3f ambient{0.18f, 0.18f, 0.2f};
    float specular = 0.35f;
    float shininess = 48.0f;
    Environment environment;
    std::vector<Light> lights;
};

// How splats combine. `over`: premultiplied "over" (a depth-only visibility pass first, or
// sorted). `additive`: summed, no occlusion. `normalised`: the front surface's splats (behind
// the visibility pass's depth) averaged with their Gaussian weights and their coverage combined,
// in any order, then blended over the target (render/normalised_blend.h): no disc's rim shows.
// Needs the Gaussian footprint.
enum class Blend { over, additive, normalised };

// Where the far-to-near order for "over" blending comes from. `unsorted` draws a depth-only
// visibility pass first (see SplatStyle); `cpu` means the records arrive sorted; `gpu` has the
// renderer cull and sort them in compute passes and draw indirectly. Sorted orders composite
// every splat behind the nearer ones, as the paper's blending does.
enum class SplatOrder { unsorted, cpu, gpu };
inline constexpr core::EnumName<SplatOrder> k_splat_order_names[] = {
    {SplatOrder::unsorted, "off"}, {SplatOrder::cpu, "cpu"}, {SplatOrder::gpu, "gpu"}};
inline const char* splat_order_name(SplatOrder o) { return core::name_of<SplatOrder>(k_splat_order_names, o); }

// Where the lighting of eqs. 24-25 is evaluated: per fragment (the paper's), or at the four
// corners of each quad and interpolated (about a quarter less time on a fill-bound device;
// the image differs by the lighting's variation across one splat).
enum class SplatShading { fragment, corner };

// What the fragment stage keeps of each splat. `gaussian`: the soft falloff, cut where its alpha
// falls below 1/255, blended over a depth-only visibility pass (or sorted). `paper`: the
// paper's flat disc (eqs. 19-23: a quad of half-size kappa s0, the unit ellipse of its
// coordinates over the sharpness, constant opacity sigmoid(o)), one pass that tests and writes
// depth, as the paper's real-time scheme draws it.
enum class Footprint { gaussian, paper };
inline constexpr core::EnumName<Footprint> k_footprint_names[] = {{Footprint::gaussian, "gaussian"}, {Footprint::paper, "paper"}};
inline const char* footprint_name(Footprint f) { return core::name_of<Footprint>(k_footprint_names, f); }

// The paper disc's half-size, in units of a record's scale s0, that closes the scenes' surfaces
// (s0 = 0.7 h, the default splat_scale). A truly maximal Poisson-disk sample at spacing h leaves
// no point farther than h from a sample (kappa 1.43), but the sampler's dart throwing is not
// quite maximal and the density control lets a triangle stretch 10 % before it adds samples:
// measured on the default scene at 1280x720, kappa 1.43 leaves pinholes on 0.085 % of the
// surface, 1.6 on 0.005 %, 1.8 none (docs/BENCHMARKS.md). Discs of radius 1.26 h, then.
inline constexpr float k_paper_closing_kappa = 1.8f;

struct SplatStyle {
    Footprint footprint = Footprint::paper;
    // Gaussian: a cap on each splat's reach in standard deviations (0: none, the 1/255 alpha
    // cut-off alone). Paper: the disc's half-size in units of s0.
    float kappa = 0.0f;
    Vec2f sharpness{1.0f, 1.0f};
    float scale_multiplier = 1.0f;
    // 0: every splat round, the paper's isotropic Gaussian. Above 0: a surfel, the Gaussian
    // flattened onto the plane of its normal, this thick along it over its width (0.1 draws
    // a disc that is a line seen edge-on): silhouettes and folds end where the surface does.
    float surfel_thickness = 0.0f;
    // Normalised blending: splats under this many pixels of standard deviation are drawn fewer
    // and larger, by the samples' thinning order (surface/thin_order.h): a fraction
    // (sigma / thin_below)^2 of them, each grown to cover as much as all did. 0: every splat.
    float thin_below = 0.0f;
    Blend blend = Blend::over;
    SplatOrder order = SplatOrder::unsorted;  // only read with Blend::over
    // Gaussian "over" blending without a sort: a depth-only pass first lays down each splat's
    // core (where its alpha reaches depth_min_alpha), pushed back by depth_push standard
    // deviations; the colour pass then tests against it without writing, so neighbouring
    // splats of one surface blend smoothly and hidden ones stay hidden. Additive blending and
    // the paper's disc need neither.
    float depth_push = 2.0f;
    // Splats whose normal faces the eye by less than this cosine are not drawn: set it (the
    // scene does, while its body is closed) when nothing behind the near surface can show.
    // Below -1: every splat is drawn.
    float cull_facing = -2.0f;
    // Only where a splat is this opaque does it write depth: a fragment that lets most of the
    // background through must not hide its own surface's neighbours' colour, nor the surface
    // behind (dark specks); splats fading in after a cut write none.
    float depth_min_alpha = 0.4f;
    // Normalised blending or the paper's disc (occluded_style): the visibility depth comes from
    // the surface mesh (render/occluder_pass.h) instead of the splats, and a fragment farther than
    // occluder_tolerance (world units, along the view axis) behind the surface the mesh shows at
    // its pixel, or twice that in front, is dropped. Needs a renderer created with options.occluders and the mesh each
    // frame (SplatRenderer::set_occluders).
    bool mesh_occluders = false;
    float occluder_tolerance = 0.0f;
    // How far the mesh's depth is pushed back for the early test (world units): farther than any
    // of the surface's own splats can lie behind it.
    float occluder_push = 0.0f;
    // The colour of the surface's inside (rgb, linear) where it shows through an opening, and
    // how much of it (a: 0 keeps each splat's own colour; 1 replaces it). Shaded splats only.
    Vec4f interior = Vec4f::Zero();
};

// The styles mesh occluders serve (with mesh_occluders set): normalised blending, and the
// paper's disc under "over" (its one depth-writing pass then runs after the occluders').
inline bool occluded_style(const SplatStyle& s) {
    return s.mesh_occluders && (s.blend == Blend::normalised || (s.blend == Blend::over && s.footprint == Footprint::paper));
}

// The scene's ground plane as drawn (render/ground.h): a disc on the plane, with a contact shadow
// under the body. The scene fills it every frame from its plane collider and the body's bounds.
struct Ground {
    bool visible = false;
    Vec3f normal{0.0f, 1.0f, 0.0f};  // into free space
    float offset = 0.0f;             // dot(normal, x) = offset on the plane
    Vec3f centre = Vec3f::Zero();    // of the drawn disc, on the plane
    float radius = 10.0f;
    bool fitted = false;             // centre and radius hold an earlier frame's disc
    // A contact shadow under each of the largest pieces (strength 0: unused).
    struct Shadow {
        Vec3f centre = Vec3f::Zero();  // the piece's centre dropped onto the plane
        float radius = 0.0f;
        float strength = 0.0f;  // 0 to 1: how dark right under it
    };
    std::array<Shadow, GROUND_SHADOWS> shadows{};
    Vec3f albedo{0.30f, 0.30f, 0.33f};
};

struct FrameInputs {
    Camera camera;
    Ground ground;
    Lighting lighting;
    SplatStyle style;
    Vec4f background{0.06f, 0.06f, 0.08f, 1.0f};
};

} // namespace pbdsplat::render
