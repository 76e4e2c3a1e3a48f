// The settings table: defaults are valid, ranges are enforced by name, and the JSON and GLSL views agree.
#include <gtest/gtest.h>

#include "error.h"
#include "settings.h"

namespace bounce {
namespace {

TEST(Settings, DefaultsAreValid) { EXPECT_NO_THROW(validate_settings(default_settings())); }

TEST(Settings, OutOfRangeValuesNameTheSetting) {
  BounceSettings s = default_settings();
  s.samples = 0;
  try {
    validate_settings(s);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'samples'"), std::string::npos);
  }
  s = default_settings();
  s.shadow_bias = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(validate_settings(s), Error);
}

TEST(Settings, JsonAndGlslListEverySettingInStructOrder) {
  const std::string& json = settings_table_json();
  const std::string& glsl = settings_glsl_block();
  std::size_t json_at = 0, glsl_at = 0;
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  json_at = json.find("\"name\":\"" #name "\"", json_at);                                                         \
  EXPECT_NE(json_at, std::string::npos) << #name;                                                                 \
  glsl_at = glsl.find(" " #name ";", glsl_at);                                                                    \
  EXPECT_NE(glsl_at, std::string::npos) << #name;
#include "bounce/settings.def"
#undef BOUNCE_SETTING
  EXPECT_NE(json.find("[\"DIRECT\",\"Direct\","), std::string::npos);
}

}  // namespace
}  // namespace bounce
