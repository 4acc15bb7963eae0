#include "asset/gltf_loader.h"

#include <cmath>
#include <cstring>
#include <functional>

#include <tiny_gltf.h>

namespace pbdsplat::asset {
namespace {

// Reads `count` elements of up to 4 components of an accessor as floats (normalised integers
// mapped to [0, 1] or [-1, 1], plain integers as their values), with every offset checked
// against its buffer: a malformed file is refused, never read past its end.
core::Result<std::vector<Eigen::Vector4f>> read_accessor(const tinygltf::Model& g, int index, const std::string& name,
                                                         const char* what) {
    if (index < 0 || size_t(index) >= g.accessors.size()) return core::make_error(name, 0, std::string(what) + ": no such accessor");
    const tinygltf::Accessor& a = g.accessors[size_t(index)];
    if (a.sparse.isSparse) return core::make_error(name, 0, std::string(what) + ": sparse accessors are not read");
    const int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (comps < 1 || comps > 4 || size <= 0) return core::make_error(name, 0, std::string(what) + ": unsupported accessor type");
    std::vector<Eigen::Vector4f> out(a.count, Eigen::Vector4f(0, 0, 0, 1));
    if (a.bufferView < 0) return out;  // all zeros, as the specification says
    if (size_t(a.bufferView) >= g.bufferViews.size()) return core::make_error(name, 0, std::string(what) + ": no such buffer view");
    const tinygltf::BufferView& v = g.bufferViews[size_t(a.bufferView)];
    if (v.buffer < 0 || size_t(v.buffer) >= g.buffers.size()) return core::make_error(name, 0, std::string(what) + ": no such buffer");
    const std::vector<unsigned char>& data = g.buffers[size_t(v.buffer)].data;
    const size_t stride = v.byteStride ? v.byteStride : size_t(comps * size);
    const size_t start = v.byteOffset + a.byteOffset;
    if (a.count > 0 && (start + (a.count - 1) * stride + size_t(comps * size) > data.size() ||
                        start + (a.count - 1) * stride + size_t(comps * size) > v.byteOffset + v.byteLength))
        return core::make_error(name, 0, std::string(what) + ": the accessor reaches past its buffer");
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char* p = data.data() + start + i * stride;
        for (int c = 0; c < comps; ++c) {
            const unsigned char* q = p + c * size;
            float x = 0.0f;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&x, q, 4); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: x = a.normalized ? float(q[0]) / 255.0f : float(q[0]); break;
            case TINYGLTF_COMPONENT_TYPE_BYTE: x = a.normalized ? std::max(float(int8_t(q[0])) / 127.0f, -1.0f) : float(int8_t(q[0])); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, q, 2); x = a.normalized ? float(s) / 65535.0f : float(s); break; }
            case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t s; std::memcpy(&s, q, 2); x = a.normalized ? std::max(float(s) / 32767.0f, -1.0f) : float(s); break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t s; std::memcpy(&s, q, 4); x = float(s); break; }
            default: return core::make_error(name, 0, std::string(what) + ": unsupported component type");
            }
            out[i][c] = x;
        }
    }
    return out;
}

// Indices read exactly (a float would round those past 2^24).
core::Result<std::vector<uint32_t>> read_indices(const tinygltf::Model& g, int index, size_t vertices, const std::string& name) {
    std::vector<uint32_t> out;
    if (index < 0) {
        out.resize(vertices);
        for (uint32_t i = 0; i < vertices; ++i) out[i] = i;
        return out;
    }
    if (size_t(index) >= g.accessors.size()) return core::make_error(name, 0, "indices: no such accessor");
    const tinygltf::Accessor& a = g.accessors[size_t(index)];
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (a.bufferView < 0 || size_t(a.bufferView) >= g.bufferViews.size() || size <= 0 || size > 4)
        return core::make_error(name, 0, "indices: missing buffer view or unsupported type");
    const tinygltf::BufferView& v = g.bufferViews[size_t(a.bufferView)];
    if (v.buffer < 0 || size_t(v.buffer) >= g.buffers.size()) return core::make_error(name, 0, "indices: no such buffer");
    const std::vector<unsigned char>& data = g.buffers[size_t(v.buffer)].data;
    const size_t stride = v.byteStride ? v.byteStride : size_t(size), start = v.byteOffset + a.byteOffset;
    if (a.count > 0 && start + (a.count - 1) * stride + size_t(size) > data.size())
        return core::make_error(name, 0, "indices: the accessor reaches past its buffer");
    out.resize(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        uint32_t x = 0;
        std::memcpy(&x, data.data() + start + i * stride, size_t(size));  // little-endian, as glTF is
        if (x >= vertices) return core::make_error(name, 0, "indices: index " + std::to_string(x) + " of " + std::to_string(vertices) + " vertices");
        out[i] = x;
    }
    return out;
}

Wrap wrap_of(int mode) {
    if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return Wrap::clamp;
    if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return Wrap::mirror;
    return Wrap::repeat;
}

Eigen::Matrix4f node_matrix(const tinygltf::Node& n) {
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    if (n.matrix.size() == 16) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m(r, c) = float(n.matrix[size_t(c * 4 + r)]);
        return m;
    }
    Eigen::Affine3f t = Eigen::Affine3f::Identity();
    if (n.translation.size() == 3) t.translate(Vec3f(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
    if (n.rotation.size() == 4)
        t.rotate(Eigen::Quaternionf(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2])).normalized());
    if (n.scale.size() == 3) t.scale(Vec3f(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
    return t.matrix();
}

struct Builder {
    const tinygltf::Model& g;
    const std::string& name;
    ModelAsset out;
    SurfaceLook look;
    std::vector<int> texture_slot;  // glTF texture -> look.textures, built on first use
    bool any_uv = false, any_colour = false;

    int32_t texture(int index) {
        if (index < 0 || size_t(index) >= g.textures.size()) return -1;
        if (texture_slot[size_t(index)] != -2) return texture_slot[size_t(index)];
        const tinygltf::Texture& t = g.textures[size_t(index)];
        texture_slot[size_t(index)] = -1;
        if (t.source < 0 || size_t(t.source) >= g.images.size()) return -1;
        const tinygltf::Image& im = g.images[size_t(t.source)];
        if (im.width <= 0 || im.height <= 0 || im.component < 1 || im.component > 4 || (im.bits != 8 && im.bits != 16) ||
            im.image.size() < size_t(im.width) * size_t(im.height) * size_t(im.component) * size_t(im.bits / 8)) {
            out.warnings.push_back(name + ": image '" + (im.uri.empty() ? im.name : im.uri) + "' could not be decoded; its material's colour is used");
            return -1;
        }
        Texture tex;
        tex.name = im.uri.empty() ? (im.name.empty() ? "image " + std::to_string(t.source) : im.name) : im.uri;
        tex.width = uint32_t(im.width);
        tex.height = uint32_t(im.height);
        tex.rgba.resize(size_t(im.width) * size_t(im.height) * 4);
        const size_t bytes = size_t(im.bits / 8);
        for (size_t p = 0; p < size_t(im.width) * size_t(im.height); ++p)
            for (int c = 0; c < 4; ++c) {
                // Grey and grey-alpha images spread their first channel over RGB.
                const int src = im.component >= 3 ? (c < im.component ? c : -1) : (c < 3 ? 0 : (im.component == 2 ? 1 : -1));
                // 16-bit: the high byte (little-endian storage puts it second).
                tex.rgba[p * 4 + size_t(c)] = src < 0 ? 255 : im.image[(p * size_t(im.component) + size_t(src)) * bytes + (bytes - 1)];
            }
        if (t.sampler >= 0 && size_t(t.sampler) < g.samplers.size()) {
            tex.wrap_u = wrap_of(g.samplers[size_t(t.sampler)].wrapS);
            tex.wrap_v = wrap_of(g.samplers[size_t(t.sampler)].wrapT);
        }
        texture_slot[size_t(index)] = int32_t(look.textures.size());
        look.textures.push_back(std::move(tex));
        return texture_slot[size_t(index)];
    }

    // The primitive's material: its base colour, and its base colour texture where it has UVs.
    Material material_of(int index, bool has_uv) {
        Material mat;
        if (index < 0 || size_t(index) >= g.materials.size()) return mat;
        const tinygltf::Material& gm = g.materials[size_t(index)];
        mat.name = gm.name;
        const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
        if (f.size() >= 3) mat.color = Vec3f(float(f[0]), float(f[1]), float(f[2])).cwiseMax(0.0f).cwiseMin(1.0f);
        if (has_uv && gm.pbrMetallicRoughness.baseColorTexture.texCoord == 0) mat.texture = texture(gm.pbrMetallicRoughness.baseColorTexture.index);
        return mat;
    }

    // Triangles from a list, a strip (every other one turned to keep the winding) or a fan.
    static std::vector<mesh::Triangle> triangles_of(int mode, const std::vector<uint32_t>& ix) {
        std::vector<mesh::Triangle> tris;
        if (mode == TINYGLTF_MODE_TRIANGLES)
            for (size_t k = 0; k + 2 < ix.size(); k += 3) tris.push_back({ix[k], ix[k + 1], ix[k + 2]});
        else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
            for (size_t k = 0; k + 2 < ix.size(); ++k)
                tris.push_back(k % 2 ? mesh::Triangle{ix[k + 1], ix[k], ix[k + 2]} : mesh::Triangle{ix[k], ix[k + 1], ix[k + 2]});
        else
            for (size_t k = 1; k + 1 < ix.size(); ++k) tris.push_back({ix[0], ix[k], ix[k + 1]});
        return tris;
    }

    core::Status primitive(const tinygltf::Primitive& p, const Eigen::Matrix4f& world) {
        if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP && p.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            out.warnings.push_back(name + ": a primitive of points or lines was skipped (only triangles make a surface)");
            return core::Status::success();
        }
        const auto pos_it = p.attributes.find("POSITION");
        if (pos_it == p.attributes.end()) return core::make_error(name, 0, "a triangle primitive without POSITION");
        auto pos = read_accessor(g, pos_it->second, name, "POSITION");
        if (!pos.ok()) return pos.error();
        auto idx = read_indices(g, p.indices, pos->size(), name);
        if (!idx.ok()) return idx.error();
        std::vector<Eigen::Vector4f> uv, col;
        if (auto it = p.attributes.find("TEXCOORD_0"); it != p.attributes.end()) {
            auto r = read_accessor(g, it->second, name, "TEXCOORD_0");
            if (!r.ok()) return r.error();
            uv = std::move(r).value();
        }
        if (auto it = p.attributes.find("COLOR_0"); it != p.attributes.end()) {
            auto r = read_accessor(g, it->second, name, "COLOR_0");
            if (!r.ok()) return r.error();
            col = std::move(r).value();
        }
        if ((!uv.empty() && uv.size() != pos->size()) || (!col.empty() && col.size() != pos->size()))
            return core::make_error(name, 0, "a primitive's attributes differ in length");
        const Material mat = material_of(p.material, !uv.empty());
        const uint32_t base = uint32_t(out.mesh.positions.size());
        for (const Eigen::Vector4f& x : pos.value()) {
            const Eigen::Vector4f w = world * Eigen::Vector4f(x.x(), x.y(), x.z(), 1.0f);
            if (!w.allFinite()) return core::make_error(name, 0, "a non-finite vertex position");
            out.mesh.positions.emplace_back(w.x(), w.y(), w.z());
        }
        // A mirroring transform turns the winding inside out; repair orients it outward anyway.
        const std::vector<mesh::Triangle> tris = triangles_of(p.mode, idx.value());
        const uint32_t material = uint32_t(look.materials.size());
        look.materials.push_back(mat);
        for (const mesh::Triangle& t : tris) {
            out.mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
            look.material.push_back(material);
            std::array<Vec2f, 3> u{};
            std::array<Vec3f, 3> c{Vec3f::Ones(), Vec3f::Ones(), Vec3f::Ones()};
            for (int k = 0; k < 3; ++k) {
                if (!uv.empty()) u[size_t(k)] = uv[t[size_t(k)]].head<2>();
                if (!col.empty()) c[size_t(k)] = col[t[size_t(k)]].head<3>().cwiseMax(0.0f).cwiseMin(1.0f);  // linear in glTF
            }
            look.uv.push_back(u);
            look.corner_color.push_back(c);
        }
        any_uv = any_uv || !uv.empty();
        any_colour = any_colour || !col.empty();
        return core::Status::success();
    }

    core::Status node(int index, const Eigen::Matrix4f& parent, int depth) {
        if (index < 0 || size_t(index) >= g.nodes.size()) return core::make_error(name, 0, "a scene refers to node " + std::to_string(index) + ", which does not exist");
        if (depth > 64) return core::make_error(name, 0, "nodes nested more than 64 deep (a cycle?)");
        const tinygltf::Node& n = g.nodes[size_t(index)];
        const Eigen::Matrix4f world = parent * node_matrix(n);
        if (n.mesh >= 0) {
            if (size_t(n.mesh) >= g.meshes.size()) return core::make_error(name, 0, "node " + std::to_string(index) + " refers to a mesh that does not exist");
            for (const tinygltf::Primitive& p : g.meshes[size_t(n.mesh)].primitives) PBDSPLAT_TRY(primitive(p, world));
        }
        for (int c : n.children) PBDSPLAT_TRY(node(c, world, depth + 1));
        return core::Status::success();
    }
};

} // namespace

core::Result<ModelAsset> load_gltf(const std::string& path, bool binary) {
    tinygltf::Model g;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromFile(&g, &err, &warn, path) : loader.LoadASCIIFromFile(&g, &err, &warn, path);
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        return core::make_error(path, 0, "not a readable glTF 2.0 file: " + (err.empty() ? std::string("tinygltf gave no reason") : err));
    }
    for (const std::string& ext : g.extensionsRequired)
        if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" || ext == "KHR_mesh_quantization")
            return core::make_error(path, 0, "needs the glTF extension " + ext + " (compressed geometry), which pbdsplat does not decode; "
                                             "export it uncompressed (e.g. gltf-transform copy, or Blender without compression)");
    Builder b{g, path, {}, {}, std::vector<int>(g.textures.size(), -2)};
    const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
    if (!g.scenes.empty()) {
        const size_t s = g.defaultScene >= 0 && size_t(g.defaultScene) < g.scenes.size() ? size_t(g.defaultScene) : 0;
        for (int n : g.scenes[s].nodes) PBDSPLAT_TRY(b.node(n, identity, 0));
    } else {
        // No scene: every mesh as it is (the specification lets a file be a library of meshes).
        for (const tinygltf::Mesh& m : g.meshes)
            for (const tinygltf::Primitive& p : m.primitives) PBDSPLAT_TRY(b.primitive(p, identity));
    }
    if (b.out.mesh.triangles.empty()) return core::make_error(path, 0, "the glTF file has no triangles in its scene: nothing to simulate");
    if (!b.any_uv) b.look.uv.clear();
    if (!b.any_colour) b.look.corner_color.clear();
    for (const std::string& line : {warn})
        if (!line.empty()) b.out.warnings.push_back(path + ": " + line.substr(0, line.find('\n')));
    if (b.look.has_colour()) {
        b.out.look = std::move(b.look);
        share_geometry(b.out);
    }
    return std::move(b.out);
}

} // namespace pbdsplat::asset
