// The settings table (settings.def) seen from C++: defaults, validation, the JSON the add-on reads, and the
// GLSL uniform block every shader gets.
#pragma once

#include <string>

#include "bounce/bounce.h"

namespace bounce {

BounceSettings default_settings();
void validate_settings(const BounceSettings& settings);  // throws Error naming the setting out of range
const std::string& settings_table_json();
const std::string& settings_glsl_block();  // `layout(std140, binding = 0) uniform Settings { ... } settings;`

}  // namespace bounce
