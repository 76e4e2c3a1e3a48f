#include "settings.h"

#include <cmath>
#include <sstream>
#include <string_view>

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

template <typename T>
std::string json_number(T value) {
  std::ostringstream s;
  s.precision(9);
  s << value;
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
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  if (!(std::isfinite(static_cast<double>(s.name)) && s.name >= static_cast<ctype>(min) &&                        \
        s.name <= static_cast<ctype>(max)))                                                                       \
    fail(BOUNCE_ERROR_INVALID_ARGUMENT, "setting '" #name "' = " + json_number(s.name) + " is outside [" +        \
                                            json_number(static_cast<ctype>(min)) + ", " +                         \
                                            json_number(static_cast<ctype>(max)) + "]");
#include "bounce/settings.def"
#undef BOUNCE_SETTING
}

SoftRange soft_range(std::string_view setting) {
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  if (setting == #name) return {static_cast<double>(smin), static_cast<double>(smax)};
#include "bounce/settings.def"
#undef BOUNCE_SETTING
  fail(BOUNCE_ERROR_INVALID_ARGUMENT, "no setting '" + std::string(setting) + "'");
}

const std::string& settings_table_json() {
  static const std::string json = [] {
    std::string out = "[";
    bool first = true;
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc)     \
  out += first ? "\n" : ",\n";                                                                                        \
  first = false;                                                                                                      \
  out += "{\"name\":\"" #name "\",\"type\":\"" #ctype "\",\"kind\":\"" #kind "\",\"label\":\"" + json_escape(label) + \
         "\",\"default\":" + json_number(static_cast<ctype>(def)) + ",\"viewport_default\":" +                        \
         json_number(static_cast<ctype>(viewport_default(#name, static_cast<double>(def)))) +                         \
         ",\"min\":" + json_number(static_cast<ctype>(min)) + ",\"max\":" + json_number(static_cast<ctype>(max)) +    \
         ",\"soft_min\":" + json_number(static_cast<ctype>(smin)) +                                                   \
         ",\"soft_max\":" + json_number(static_cast<ctype>(smax)) + ",\"flags\":" + json_number(flags) +              \
         ",\"group\":\"" + json_escape(group) + "\",\"items\":" + json_enum_items(items) + ",\"description\":\"" +    \
         json_escape(desc) + "\"}";
#include "bounce/settings.def"
#undef BOUNCE_SETTING
    return out + "\n]";
  }();
  return json;
}

const std::string& settings_glsl_block() {
  static const std::string block = [] {
    std::string out = "layout(std140, binding = 0) uniform Settings {\n";
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  out += "  " #glsl_type " " #name ";\n";
#include "bounce/settings.def"
#undef BOUNCE_SETTING
    return out + "} settings;\n";
  }();
  return block;
}

}  // namespace bounce
