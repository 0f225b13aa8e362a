// What the FE check's tests share (tests/fecheck, tests/service): skipping without tetgen and
// ccx, and a check that a text holds a part.
#pragma once

#include <string>

#include "fecheck/tools.h"
#include "gtest/gtest.h"

// The end-to-end tests need both tools on the PATH (scripts/install-deps.sh installs them).
#define SKIP_WITHOUT_FE_TOOLS()                                                \
  if (absl::Status fe_tools = femsimp::fecheck::LocateTools(); !fe_tools.ok()) \
  GTEST_SKIP() << fe_tools.message()

#define EXPECT_HAS(text, part)                                                                 \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (part) << "' not in:\n" \
                                                             << (text)
