// The settings table (settings.def) seen from C++: defaults, validation, the JSON the add-on reads, and the
// GLSL uniform block every shader gets.
#pragma once

#include <string>
#include <string_view>

#include "bounce/bounce.h"

namespace bounce {

BounceSettings default_settings();
void validate_settings(const BounceSettings& settings);  // throws Error naming the setting out of range

// A setting's soft range: what the Blender slider offers and the span a plan may choose from.
struct SoftRange {
  double min = 0.0, max = 0.0;
};
SoftRange soft_range(std::string_view name);  // throws Error for a name the table does not have
const std::string& settings_table_json();
const std::string& settings_glsl_block();  // `layout(std140, binding = 0) uniform Settings { ... } settings;`

}  // namespace bounce
