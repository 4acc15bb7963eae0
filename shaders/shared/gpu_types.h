// GPU-side structures shared by C++ and GLSL: one definition, so the two can never drift.
// C++ includes this inside namespace pbdsplat::gpu_types and static_asserts every size; GLSL
// includes it as is (std140 for uniform blocks, vertex attributes for the splat record).
#ifndef PBDSPLAT_GPU_TYPES_H
#define PBDSPLAT_GPU_TYPES_H

#ifdef __cplusplus
#include <cstdint>
namespace pbdsplat::gpu_types {
using uint = uint32_t;
struct alignas(16) vec4 { float x, y, z, w; };
struct alignas(16) mat4 { float m[16]; };  // column-major, as GLSL reads it
#define PBDSPLAT_GPU_SIZE(T, n) static_assert(sizeof(T) == (n), #T ": C++ and GLSL (std140) layouts disagree")
#else
#define PBDSPLAT_GPU_SIZE(T, n)
#endif

// ---- One Gaussian as the splat pass reads it (vertex attributes, binding 0) -----------------
// position   : R32G32B32_SFLOAT  world-space centre mu (the particle position, eq. 12)
// normal     : R16G16_SNORM      octahedral-encoded unit normal; the lowest two bits of each
//              component hold the record's model (x's its low bits, y's its high bits), whose
//              centre its position-based environment lookups look out from (env_centers)
// color      : R8G8B8A8_UNORM    linear albedo rgb; a = fade-in factor (1 when settled)
// scale_opac : R16G16_SFLOAT     x = isotropic std-dev s0 in world units, y = opacity logit o
// curvature  : R16G16B16A16_SFLOAT how the surface's normal turns across the splat: the
//              symmetric 3x3 S, per world unit, so that a step p in the splat's tangent plane
//              turns its normal by S p. S n = 0, so three numbers hold it: x, y, z are S's 2x2
//              block (ii, ij, jj) on the two axes other than d (0, 1 or 2, the normal's
//              largest component), i = d+1, j = d+2 (mod 3); splat_curvature() rebuilds the rest.
//              xyz zero draws one normal per splat (the paper's flat shading). w holds the
//              integer d + 4 (SPLAT_THIN_LEVELS - l) + 32 k: l is the splat's level in the
//              thinning order (surface/thin_order.h; 0 stored, the top: never thinned), k (0-63)
//              its rank within the level (splat_thin() in splat_footprint.glsl).
#define SPLAT_RECORD_SIZE 32
#define SPLAT_OFFSET_POSITION 0
#define SPLAT_OFFSET_NORMAL 12
#define SPLAT_OFFSET_COLOR 16
#define SPLAT_OFFSET_SCALE_OPACITY 20
#define SPLAT_OFFSET_CURVATURE 24
#define SPLAT_THIN_LEVELS 4
// A scene's models are lit from their own centres (the record's model, above); in a scene of
// more models, those past the last share its entry, which then holds the centre of them all.
#define SPLAT_ENV_CENTERS 16

// ---- Anisotropic splats (optional storage stream, binding 3 of the splat pass) --------------
// Per record, the three axes of its Gaussian in world units (columns of R S, so the covariance
// is A A^T; any three vectors whose A A^T is the covariance will do): 9 IEEE halfs, x y z of
// each axis in turn, and one half of padding. The record's own scale is then the longest axis
// (it bounds culling and the visibility pass's push).
#define SPLAT_SHAPE_SIZE 20

// ---- View-dependent colour (optional storage stream, binding 4 of the splat pass) -----------
// Per record, the spherical-harmonic coefficients of degrees 1-3 of a trained 3DGS file, as its
// f_rest_* columns hold them: 15 per channel, red first, then green, then blue (45 IEEE halfs,
// three of padding). The record's colour is degree 0's.
#define SPLAT_SH_COEFFS 45
#define SPLAT_SH_SIZE 96

// ---- Textured splats (optional storage stream, binding 6; the textures at binding 7) --------
// Per record, where a textured model's texture lies on the splat, so the fragment stage reads
// the texture under each pixel instead of one colour per splat: the texture coordinates at the
// centre (two floats), their world gradients du and dv (IEEE halfs, x y z each: the change of u
// and v per world unit along the surface), the texture (a uint16 into binding 7's array;
// SPLAT_NO_TEXTURE draws the record's own colour) and how far from its centre the splat may read
// (an IEEE half, world units along the surface: short of a seam, where the coordinates jump to
// another part of the texture), and the colour the texture multiplies (unorm8 rgb, linear; a
// unused). 32 bytes.
#define SPLAT_TEXCOORD_SIZE 32
#define SPLAT_MAX_TEXTURES 8
#define SPLAT_NO_TEXTURE 0xFFFFu

// ---- Splat footprints (specialization constant 2 of the splat pipelines) --------------------
#define SPLAT_FOOTPRINT_GAUSSIAN 0u  // soft Gaussian, cut where its alpha falls below 1/255
#define SPLAT_FOOTPRINT_PAPER 1u     // the paper's flat elliptical disc (eqs. 22-23), one pass

// ---- Per-frame constants (set 0, binding 0) ---------------------------------------------------
#define PBDSPLAT_MAX_LIGHTS 4
struct FrameUniforms {
    mat4 view;         // world -> view
    mat4 proj;         // view -> clip (Vulkan: y down, z in [0,1])
    vec4 camera_pos;   // xyz: eye in world space
    vec4 viewport;     // width, height, 1/width, 1/height
    vec4 light_dir;    // xyz: unit direction from the surface towards the light; w: intensity
    vec4 light_color;  // rgb
    vec4 ambient;      // rgb ambient light; w: specular strength
    vec4 splat;        // x: kappa: the Gaussian's cap on its reach in std devs (0: none), the
                       // paper disc's half-size in s0; y, z: sharpness sigma_x, sigma_y;
                       // w: global scale multiplier
    vec4 material;     // x: shininess; y: surfel thickness along the normal over the width
                       // (0: the paper's round splats); z: splats under this many pixels of
                       // standard deviation are thinned (0: none, splat_thin()); w unused
    vec4 interior;     // rgb: the colour of the surface's inside seen through an opening;
                       // a: how much it replaces a splat's own there (0: not at all)
    vec4 visibility;   // x: depth push of the visibility pass, in splat std devs;
                       // y: splats whose normal faces the eye by less than this cosine are
                       // culled (a closed, opaque body); below -1: none;
                       // z: the least alpha (opacity x fade x falloff) that writes depth
                       // w: mesh occluders' tolerance along the view axis, world units
    // Environment lighting (paper eqs. 24-25, section 7.2).
    vec4 environment;  // x: sampling (0 off: ambient only, 1 position, 2 normal, 3 hybrid);
                       // y: diffuse weight k_d; z: specular weight; w: intensity
    vec4 env_center;   // xyz: the point position-based lookups look out from; w: light count
    vec4 env_sh[9];    // irradiance as 9 spherical-harmonic coefficients (rgb), cosine lobe applied
    vec4 env_centers[SPLAT_ENV_CENTERS];  // xyz: each model's centre, for its position-based lookups
    // Extra direct lights (eq. 25), besides the key light above.
    vec4 light_position[PBDSPLAT_MAX_LIGHTS];  // xyz: position, or direction to the light; w: 0 dir, 1 point, 2 spot
    vec4 light_radiance[PBDSPLAT_MAX_LIGHTS];  // rgb: colour * intensity; w: range (point, spot)
    vec4 light_spot[PBDSPLAT_MAX_LIGHTS];      // xyz: spot axis, away from the light; w: unused
    vec4 light_cone[PBDSPLAT_MAX_LIGHTS];      // x: cos of the inner angle, y: cos of the outer angle
};
PBDSPLAT_GPU_SIZE(FrameUniforms, 2 * 64 + 9 * 16 + 11 * 16 + SPLAT_ENV_CENTERS * 16 + 4 * PBDSPLAT_MAX_LIGHTS * 16);

// ---- The ground pass (render/ground.h): push constants ----------------------------------------
#define GROUND_SHADOWS 4
struct GroundPush {
    vec4 plane;   // xyz: unit normal into free space; w: offset (dot(n, x) = offset on the plane)
    vec4 disc;    // xyz: centre of the drawn disc on the plane; w: its radius
    vec4 albedo;  // rgb: the ground's colour
    // The contact shadows, one under each of the largest pieces: xyz: its centre dropped onto
    // the plane; w: the shadow's radius. Their strengths (0 to 1) in `strength`, 0 where unused.
    vec4 shadow[GROUND_SHADOWS];
    vec4 strength;
};
PBDSPLAT_GPU_SIZE(GroundPush, 128);

// ---- GPU depth sort (render/gpu_sort.h): push constants of every sort kernel ----------------
// The control block (storage, 32-bit words) the sort leaves for the draw: the visible count,
// then the indirect arguments of each splat path.
#define SORT_CONTROL_VISIBLE 0    // splats that survived culling
#define SORT_CONTROL_DRAW 1       // VkDrawIndirectCommand, one point per splat (geometry path)
#define SORT_CONTROL_DRAW_PULL 5  // VkDrawIndirectCommand, six vertices per splat (vertex pulling)
#define SORT_CONTROL_MESH 9       // VkDrawMeshTasksIndirectCommandEXT (mesh path)
#define SORT_CONTROL_WORDS 12
#define SORT_MESH_GROUP 32        // splats per mesh-shader workgroup (SPLATS_PER_GROUP)
struct SortPush {
    vec4 depth_row;   // view-space z = dot(depth_row, vec4(p, 1)); farther is more negative
    vec4 planes[4];   // the frustum's side planes in world space, normalised, inside positive
    vec4 limits;      // x: near distance, y: far distance, z: cull radius per unit of splat scale
    uint count;       // input records this frame
    uint shift;       // radix pass: the digit's lowest bit
    uint src_offset;  // radix pass: where the keys and values are read (0 or capacity)
    uint dst_offset;  // ... and written
    uint tiles;       // tiles of SORT_TILE elements covering `count`
    uint scan_length; // scan: entries in the tile-count array
    uint write_total; // scan: 1 = store the total as the visible count
    uint pad;
};
PBDSPLAT_GPU_SIZE(SortPush, 128);

#ifdef __cplusplus
} // namespace pbdsplat::gpu_types
#endif
#endif
