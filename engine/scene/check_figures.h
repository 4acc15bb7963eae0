#pragma once
// The figures `pbdsplat check` reports for a whole run, by the names a scene's [expect] table
// and the check's JSON give them: one list, so a name a scene file may bound is always one the
// check measures.
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace pbdsplat::scene {

struct CheckReport;

struct CheckFigure {
    const char* name;
    const char* meaning;
};
std::span<const CheckFigure> check_figures();
bool is_check_figure(std::string_view name);
// The figure's value in `report`; none where it was not measured (the coverage figures without
// a device).
std::optional<double> check_figure(const CheckReport& report, std::string_view name);

// Each bound of a scene's [expect] table against a report: met, or broken; a figure the run
// could not measure (coverage without a device) has no value and counts as met, shown so.
struct ExpectOutcome {
    ExpectBound bound;
    std::optional<double> value;
    bool met = true;
};
std::vector<ExpectOutcome> hold_to_expect(const ExpectDesc& expect, const CheckReport& report);

} // namespace pbdsplat::scene
