// Shading shared by the splat and mesh passes (paper eqs. 24-25): environment terms looked up
// by position, normal or both (section 7.2), plus the key light and up to four point, spot or
// directional lights. Needs `frame` (FrameUniforms) and `env_map` declared before inclusion.
#ifndef PBDSPLAT_SHADING_GLSL
#define PBDSPLAT_SHADING_GLSL

const float k_pi = 3.14159265358979;

vec3 env_radiance(vec3 d) {
    const vec2 uv = vec2(atan(d.z, d.x) / (2.0 * k_pi) + 0.5, acos(clamp(d.y, -1.0, 1.0)) / k_pi);
    return textureLod(env_map, uv, 0.0).rgb;
}

// Irradiance from the nine coefficients (cosine lobe already applied on the CPU).
vec3 env_irradiance(vec3 n) {
    const vec4 b0 = vec4(0.282095, 0.488603 * n.y, 0.488603 * n.z, 0.488603 * n.x);
    const vec4 b1 = vec4(1.092548 * n.x * n.y, 1.092548 * n.y * n.z, 0.315392 * (3.0 * n.z * n.z - 1.0), 1.092548 * n.x * n.z);
    const float b8 = 0.546274 * (n.x * n.x - n.y * n.y);
    return b0.x * frame.env_sh[0].rgb + b0.y * frame.env_sh[1].rgb + b0.z * frame.env_sh[2].rgb + b0.w * frame.env_sh[3].rgb +
           b1.x * frame.env_sh[4].rgb + b1.y * frame.env_sh[5].rgb + b1.z * frame.env_sh[6].rgb + b1.w * frame.env_sh[7].rgb +
           b8 * frame.env_sh[8].rgb;
}

// Blinn-Phong response to one light of radiance `radiance` arriving from direction l.
vec3 direct_light(vec3 albedo, vec3 n, vec3 t, vec3 l, vec3 radiance) {
    const float nl = max(dot(n, l), 0.0);
    if (nl <= 0.0) return vec3(0.0);
    const float spec = pow(max(dot(n, normalize(l + t)), 0.0), frame.material.x);
    return (albedo * nl + frame.ambient.w * spec) * radiance;
}

// The normal turned towards the eye: the mesh raster lights a surface from the side that is
// seen (the inside of a cut body faces the camera through the opening).
vec3 seen_side(vec3 n, vec3 world) { return dot(n, frame.camera_pos.xyz - world) < 0.0 ? -n : n; }

// The normal a splat is lit with, when it faces away from the eye. An opaque, depth-tested disc
// that still shows is a surface the eye sees: the inside of an opened body, or a disc that a
// fold or crease puts in front of its own surface; lit from the seen side, as the mesh raster
// does, instead of as a dark speck. A soft Gaussian's fringe shows whatever lies behind it, the
// far side of a closed body around its silhouette included: turned fully round, that far side
// would ring the silhouette with light; laid onto the view plane instead, it is lit as the
// grazing surface at the silhouette that it stands for.
// Normalised blending's averaged surface (`opaque_surface`) is both: a splat facing just away
// stands past a silhouette (laid onto the view plane: turned round, the top of a balloon's
// outline would be lit as a surface facing down, a dark fringe), one facing clearly away is the
// inside of an opened body (seen side). Between the two the normals are mixed, so the inside's
// shading has no seam where it turns past the angle.
vec3 splat_lit_normal(vec3 n, vec3 world, bool opaque_disc, bool opaque_surface) {
    if (opaque_disc) return seen_side(n, world);
    const vec3 t = normalize(frame.camera_pos.xyz - world);
    const float d = dot(n, t);
    if (d >= 0.0) return n;
    const vec3 laid = normalize(n - d * t + 1e-4 * t);
    if (!opaque_surface) return laid;
    return normalize(mix(laid, -n, smoothstep(0.15, 0.45, -d)));
}

// The centre a model's position-based lookups look out from.
vec3 env_centre(uint model) { return frame.env_centers[min(model, uint(SPLAT_ENV_CENTERS - 1))].xyz; }

vec3 shade(vec3 albedo, vec3 n, vec3 world, uint model) {
    const vec3 t = normalize(frame.camera_pos.xyz - world);  // towards the eye
    vec3 color = direct_light(albedo, n, t, frame.light_dir.xyz, frame.light_color.rgb * frame.light_dir.w);

    const int mode = int(frame.environment.x + 0.5);
    if (mode == 0) {
        color += albedo * frame.ambient.rgb;
    } else {
        // Eq. 24: p is the world position seen from the body's centre (its model's).
        const vec3 rel = world - env_centre(model);
        const vec3 p = dot(rel, rel) > 1e-12 ? normalize(rel) : n;
        const vec3 diffuse_dir = mode == 1 ? p : n;
        const vec3 specular_dir = mode == 2 ? n : p;
        const float shininess = frame.material.x;
        const float g = (shininess + 2.0) / (shininess + 8.0);  // brighter, tighter lobes for shinier materials
        const vec3 e_d = albedo * env_irradiance(diffuse_dir) / k_pi * frame.environment.y;
        const vec3 e_s = env_radiance(reflect(-t, specular_dir)) * frame.ambient.w * frame.environment.z * g;
        color += (e_d + e_s) * frame.environment.w;
    }

    // Eq. 25: point, spot and directional lights.
    const int lights = int(frame.env_center.w + 0.5);
    for (int k = 0; k < lights; ++k) {
        const vec4 lp = frame.light_position[k];
        const int type = int(lp.w + 0.5);
        vec3 l = lp.xyz;
        float attenuation = 1.0;
        if (type != 0) {
            const vec3 to_light = lp.xyz - world;
            const float d = length(to_light);
            l = to_light / max(d, 1e-6);
            const float fall = clamp(1.0 - d / frame.light_radiance[k].w, 0.0, 1.0);
            attenuation = fall * fall;
            if (type == 2) attenuation *= smoothstep(frame.light_cone[k].y, frame.light_cone[k].x, dot(-l, frame.light_spot[k].xyz));
        }
        color += direct_light(albedo, n, t, l, frame.light_radiance[k].rgb * attenuation);
    }
    return color;
}

#endif
