#pragma once
// Where test models live. They are never copied into the repository: they are found at run
// time in $PBDSPLAT_MODELS (a ':'-separated list), ./models, and ../shared/models beside the
// working directory or the source tree.
#include <optional>
#include <string>
#include <vector>

namespace pbdsplat::asset {

std::vector<std::string> model_search_path();

// The first existing file `name` (e.g. "teapot.obj") along the search path; a path that
// exists as given is returned unchanged.
std::optional<std::string> find_model(const std::string& name);

} // namespace pbdsplat::asset
