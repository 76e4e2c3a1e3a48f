#include "settings.h"

#include <cmath>
#include <cstddef>
#include <iterator>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>

#include "error.h"

namespace bounce {

namespace {

std::string json_escape(const char* text) {
  std::string out;
  for (const char* c = text; *c; ++c) {
    switch (*c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        out += *c;
    }
  }
  return out;
}

// "ID:Label:Tooltip|..." -> [["ID","Label","Tooltip"],...]
std::string json_enum_items(const std::string& items) {
  std::string out = "[";
  std::size_t start = 0;
  bool first = true;
  while (start < items.size()) {
    std::size_t end = items.find('|', start);
    if (end == std::string::npos) end = items.size();
    const std::string item = items.substr(start, end - start);
    const std::size_t a = item.find(':');
    const std::size_t b = item.find(':', a + 1);
    out += first ? "[" : ",[";
    out += "\"" + json_escape(item.substr(0, a).c_str()) + "\",\"" +
           json_escape(item.substr(a + 1, b - a - 1).c_str()) + "\",\"" + json_escape(item.substr(b + 1).c_str()) +
           "\"]";
    first = false;
    start = end + 1;
  }
  return out + "]";
}

// One row per setting of settings.def, its numbers as its C type holds them. The functions below loop over the
// rows: code expanded once per setting made one function of some thousand string temporaries, which took the
// sanitizer build minutes to compile.
struct SettingRow {
  const char* name;
  const char* ctype;
  const char* glsl_type;
  const char* kind;
  const char* label;
  bool integer;
  double default_value, min, max, soft_min, soft_max;
  int flags;
  const char* group;
  const char* items;
  const char* description;
};

constexpr SettingRow kSettingRows[] = {
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  {#name,                                                                                                         \
   #ctype,                                                                                                        \
   #glsl_type,                                                                                                    \
   #kind,                                                                                                         \
   label,                                                                                                         \
   std::is_integral_v<ctype>,                                                                                     \
   static_cast<double>(static_cast<ctype>(def)),                                                                  \
   static_cast<double>(static_cast<ctype>(min)),                                                                  \
   static_cast<double>(static_cast<ctype>(max)),                                                                  \
   static_cast<double>(static_cast<ctype>(smin)),                                                                 \
   static_cast<double>(static_cast<ctype>(smax)),                                                                 \
   flags,                                                                                                         \
   group,                                                                                                         \
   items,                                                                                                         \
   desc},
#include "bounce/settings.def"
#undef BOUNCE_SETTING
};

// A value as the setting's C type prints it: integers whole, floats to the 9 digits that round-trip.
std::string json_number(const SettingRow& row, double value) {
  if (row.integer) return std::to_string(static_cast<long long>(value));
  std::ostringstream s;
  s.precision(9);
  s << static_cast<float>(value);
  return s.str();
}

// The default of a setting's `viewport_` variant (BOUNCE_VIEWPORT_DEFAULT), else `final_default`.
double viewport_default(std::string_view name, double final_default) {
#define BOUNCE_SETTING(ctype, glsl_type, kind, setting, label, def, min, max, smin, smax, flags, group, items, desc)
#define BOUNCE_VIEWPORT_DEFAULT(setting, def) \
  if (name == #setting) return def;
#include "bounce/settings.def"
#undef BOUNCE_VIEWPORT_DEFAULT
#undef BOUNCE_SETTING
  return final_default;
}

std::string setting_json(const SettingRow& row) {
  const double viewport = viewport_default(row.name, row.default_value);
  return std::string("{\"name\":\"") + row.name + "\",\"type\":\"" + row.ctype + "\",\"kind\":\"" + row.kind +
         "\",\"label\":\"" + json_escape(row.label) + "\",\"default\":" + json_number(row, row.default_value) +
         ",\"viewport_default\":" + json_number(row, viewport) + ",\"min\":" + json_number(row, row.min) +
         ",\"max\":" + json_number(row, row.max) + ",\"soft_min\":" + json_number(row, row.soft_min) +
         ",\"soft_max\":" + json_number(row, row.soft_max) + ",\"flags\":" + std::to_string(row.flags) +
         ",\"group\":\"" + json_escape(row.group) + "\",\"items\":" + json_enum_items(row.items) +
         ",\"description\":\"" + json_escape(row.description) + "\"}";
}

}  // namespace

BounceSettings default_settings() {
  BounceSettings s{};
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  s.name = static_cast<ctype>(def);
#include "bounce/settings.def"
#undef BOUNCE_SETTING
  return s;
}

void validate_settings(const BounceSettings& s) {
  const double values[] = {
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  static_cast<double>(s.name),
#include "bounce/settings.def"
#undef BOUNCE_SETTING
  };
  static_assert(std::size(values) == std::size(kSettingRows));
  for (std::size_t i = 0; i < std::size(values); ++i) {
    const SettingRow& row = kSettingRows[i];
    if (!(std::isfinite(values[i]) && values[i] >= row.min && values[i] <= row.max))
      fail(BOUNCE_ERROR_INVALID_ARGUMENT, std::string("setting '") + row.name + "' = " + json_number(row, values[i]) +
                                              " is outside [" + json_number(row, row.min) + ", " +
                                              json_number(row, row.max) + "]");
  }
}

SoftRange soft_range(std::string_view setting) {
  for (const SettingRow& row : kSettingRows)
    if (setting == row.name) return {row.soft_min, row.soft_max};
  fail(BOUNCE_ERROR_INVALID_ARGUMENT, "no setting '" + std::string(setting) + "'");
}

const std::string& settings_table_json() {
  static const std::string json = [] {
    std::string out = "[";
    for (const SettingRow& row : kSettingRows) out += (&row == kSettingRows ? "\n" : ",\n") + setting_json(row);
    return out + "\n]";
  }();
  return json;
}

const std::string& settings_glsl_block() {
  static const std::string block = [] {
    std::string out = "layout(std140, binding = 0) uniform Settings {\n";
    for (const SettingRow& row : kSettingRows) out += std::string("  ") + row.glsl_type + " " + row.name + ";\n";
    return out + "} settings;\n";
  }();
  return block;
}

}  // namespace bounce
