#pragma once
// Where the camera stands when a scene does not place it. The default camera looks at the origin
// from 3 units in front, which frames one model fitted to the default 2-unit diagonal; models
// placed elsewhere (a few [[bodies]] spread on a table, one dropped from high up) would be out
// of sight, so a scene without [render.camera] eye or target that the default view misses is
// framed instead: the box of the models and of where they would land on the ground, seen from in
// front and a little above, as a model file's
// default scene is (scene/model_scene.h).
#include <span>

#include "mesh/triangle_mesh.h"
#include "render/frame_inputs.h"

namespace pbdsplat::scene {

// `lens` with its eye and target moved so that the box's bounding sphere fills the frame's
// height (its width where `aspect` is below 1), from in front (+z) and 17 degrees above.
render::Camera framing_camera(const mesh::Bounds& box, const render::Camera& lens, float aspect);

// Whether every point projects inside the central `margin` of the image, in front of the near
// plane, and (with `least_span` above 0) the points span at least that share of the image's
// width or height: a model of 2 cm in the default view is a dot.
bool camera_sees(const render::Camera& camera, std::span<const Vec3f> points, float aspect, float margin = 0.95f, float least_span = 0.0f);

} // namespace pbdsplat::scene
