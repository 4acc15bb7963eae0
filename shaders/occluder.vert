#version 460
// Occluder pass (render/occluder_pass.h): the surface mesh's triangles, both sides. Depth is
// written pushed back along each view ray, so that the splats of the surface itself pass the
// accumulation's depth test while everything well behind it is rejected early; the colour
// target keeps the unpushed distance along the view axis for the accumulation's own test.
layout(location = 0) in vec4 in_position;

layout(push_constant) uniform Push {
    mat4 view_proj;
    vec4 view_z;    // view-space z = dot(view_z.xyz, p) + view_z.w (negative in front of the eye)
    vec4 eye_push;  // xyz: the eye; w: how far depth is pushed back, world units
} push;

layout(location = 0) out float v_depth;

void main() {
    const vec3 p = in_position.xyz;
    v_depth = -(dot(push.view_z.xyz, p) + push.view_z.w);
    const vec3 ray = p - push.eye_push.xyz;
    const float len = length(ray);
    const vec3 pushed = len > 0.0 ? p + ray * (push.eye_push.w / len) : p;
    gl_Position = push.view_proj * vec4(pushed, 1.0);
}
