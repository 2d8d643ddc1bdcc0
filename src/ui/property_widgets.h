// Dear ImGui widgets generated from declared properties (base/properties.h): one widget per
// property, chosen by its type and range, with the doc line and paper citation as tooltip.
// The viewer shows every technique's parameters this way, with no per-technique UI code.
#pragma once

#include "base/properties.h"

namespace veil::ui {

// Draws the widgets of `schema` for `values` (a JSON object of effective values, as
// Properties::values() gives) and writes edits back. Returns true when a value changed;
// edited values stay within the declared ranges.
bool propertyWidgets(const PropertySchema& schema, nlohmann::json& values);

} // namespace veil::ui
