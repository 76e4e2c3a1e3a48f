// The C API boundary: status codes, last-error text, argument checks; no GL needed.
#include <gtest/gtest.h>

#include <string>

#include "bounce/bounce.h"
#include "gl/objects.h"

TEST(Api, VersionAndSettingsSize) {
  EXPECT_STREQ(bounce_version(), BOUNCE_VERSION_STRING);
  EXPECT_EQ(bounce_api_version(), BOUNCE_API_VERSION);
  EXPECT_EQ(bounce_settings_size(), sizeof(BounceSettings));
}

TEST(Api, NullArgumentsAreReportedNotCrashed) {
  EXPECT_EQ(bounce_mesh_set(nullptr, 1, nullptr), BOUNCE_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bounce_last_error()).find("engine is NULL"), std::string::npos);
  EXPECT_EQ(bounce_engine_create(nullptr, nullptr), BOUNCE_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bounce_settings_validate(nullptr), BOUNCE_ERROR_INVALID_ARGUMENT);
  bounce_engine_destroy(nullptr);
}

TEST(Api, LastErrorClearsOnSuccess) {
  EXPECT_EQ(bounce_settings_validate(nullptr), BOUNCE_ERROR_INVALID_ARGUMENT);
  BounceSettings settings;
  bounce_settings_defaults(&settings);
  EXPECT_EQ(bounce_settings_validate(&settings), BOUNCE_OK);
  EXPECT_STREQ(bounce_last_error(), "");
}

TEST(Api, AovTable) {
  EXPECT_EQ(bounce_aov_channels(BOUNCE_AOV_COMBINED), 4);
  EXPECT_EQ(bounce_aov_channels(BOUNCE_AOV_DEPTH), 1);
  EXPECT_EQ(bounce_aov_channels(BOUNCE_AOV_COUNT), 0);
  EXPECT_STREQ(bounce_aov_name(BOUNCE_AOV_NORMAL), "Normal");
  EXPECT_STREQ(bounce_aov_name(-1), "");
}

TEST(Api, GlErrorsShowTheirNameAndHexCode) {
  EXPECT_EQ(bounce::gl::error_name(GL_INVALID_VALUE), "GL_INVALID_VALUE (0x0501)");  // was "0x1281", its decimal
  EXPECT_EQ(bounce::gl::error_name(0x8cd6), "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT (0x8cd6)");
  EXPECT_EQ(bounce::gl::error_name(0x1234), "0x1234");
}
