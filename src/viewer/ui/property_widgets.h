// Dear ImGui widgets generated from declared properties (base/properties.h): one widget per
// property, chosen by its type and range, with the doc line and paper citation as tooltip.
// The viewer shows every technique's parameters this way, with no per-technique UI code.
// Widgets are laid out as a form: the property's full key (as `--set` spells it) in a label
// column as wide as the longest key, the widget filling the rest of the line (on a line of
// its own when the panel is too narrow), the tooltip on both.
#pragma once

#include "base/properties.h"

#include <string>
#include <vector>

namespace veil::ui {

// Draws the widgets of `schema` for `values` (a JSON object of effective values, as
// Properties::values() gives) and writes edits back, but none for the keys in `hidden` (which
// mean nothing for this object: a volume's temperature settings without a temperature grid).
// Returns true when a value changed; edited values stay within the declared ranges.
bool propertyWidgets(const PropertySchema& schema, nlohmann::json& values,
                     const std::vector<std::string>& hidden = {});

// The width a widget of `type` needs to show its value whole: 6 em for one field; for a
// colour or vector its three fields ("R:0.550" in a colour's) and the colour square.
float minimumWidgetWidth(PropertyType type);

// The width of a label column holding each of `labels` whole.
float labelColumnWidth(const std::vector<std::string>& labels);
// A form row's label: draws `label` in a column `width` wide and leaves the cursor where the
// row's widget goes, with that widget's width set to fill the line; when less than
// `minWidget` (default 6 em) is left beside the label, the widget takes the line below. Give
// the widget a hidden label ("##key"). `tip` (when not empty) shows on hovering the label.
void formLabel(const std::string& label, float width, const std::string& tip = "",
               float minWidget = 0.0f);

// A JSON object (a technique's statistics) as a two-column table: key, value; nested objects
// flattened to dotted keys, numbers to 4 significant digits (integers in full), arrays inline.
void jsonTable(const char* id, const nlohmann::json& values);

} // namespace veil::ui
