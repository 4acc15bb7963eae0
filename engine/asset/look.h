#pragma once
// What a model looks like, as its file says: per-triangle texture coordinates and corner
// colours, a material per triangle (base colour, base-colour texture) and the textures. Kept on
// the model's own full-resolution triangles, so the colour of any point of its surface is read
// where it is, never interpolated from a decimated copy.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::asset {

enum class Wrap : uint8_t { repeat, clamp, mirror };

// An 8-bit RGBA image, sRGB-encoded as files store colour; texel rows top first, and texture
// coordinates with v down (glTF's convention: OBJ's v is flipped when it is read).
struct Texture {
    std::string name;  // the file (or the glTF image) it came from, for messages
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
    Wrap wrap_u = Wrap::repeat, wrap_v = Wrap::repeat;

    // Linear RGB at (u, v): the four nearest texels decoded from sRGB, then blended bilinearly
    // (texel centres at half-integers, as GPUs sample).
    Vec3f sample(const Vec2f& uv) const;
};

struct Material {
    std::string name;
    Vec3f color = Vec3f::Ones();  // linear; multiplies the texture and the vertex colours
    int32_t texture = -1;         // into SurfaceLook::textures
};

struct SurfaceLook {
    // The surface as loaded (positions move with the model's transform; triangles as in the file).
    std::vector<Vec3f> positions;
    std::vector<mesh::Triangle> triangles;
    // Per triangle, each empty when the file has none.
    std::vector<std::array<Vec2f, 3>> uv;
    std::vector<std::array<Vec3f, 3>> corner_color;  // linear
    std::vector<uint32_t> material;
    std::vector<Material> materials;
    std::vector<Texture> textures;

    // Anything that varies over the surface or differs from a plain white material.
    bool has_colour() const;
    // Linear RGB at barycentric (b1, b2) of triangle t.
    Vec3f color_at(uint32_t t, const Vec2f& bary) const;
    // What color_at multiplies, apart: the texture (-1 for none) at its coordinates, and the
    // material and corner colours together (the tint), for a renderer that samples the texture.
    struct Parts {
        Vec3f tint = Vec3f::Ones();
        int32_t texture = -1;
        Vec2f uv = Vec2f::Zero();
    };
    Parts parts_at(uint32_t t, const Vec2f& bary) const;
};

// sRGB-encoded byte to linear [0, 1].
float srgb_to_linear(uint8_t v);
// sRGB-encoded colour in [0, 1] to linear (vertex colours in files are stored as seen).
Vec3f srgb_to_linear(const Vec3f& c);

} // namespace pbdsplat::asset
