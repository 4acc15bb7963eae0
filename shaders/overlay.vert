#version 460
// Overlay pass: one triangle covering the target. The overlay image keeps one texel per window
// pixel from the top-left corner, so a window larger than the overlay shows it at its size.
layout(push_constant) uniform Push { vec2 texels_per_target; } push;
layout(location = 0) out vec2 v_uv;

void main() {
    const vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    v_uv = p * push.texels_per_target;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
