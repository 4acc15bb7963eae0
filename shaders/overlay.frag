#version 460
// Overlay pass: the demo's text and strokes, premultiplied, over the presented image.
layout(set = 0, binding = 0) uniform sampler2D overlay;
layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

void main() { out_color = all(lessThanEqual(v_uv, vec2(1.0))) ? texture(overlay, v_uv) : vec4(0.0); }
