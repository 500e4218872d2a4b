#pragma once
// expect_input_error(call, part): the call throws InputError, on one line, saying `part`.

#include <gtest/gtest.h>

#include <string>

#include "canopy/common/error.h"

namespace canopy::ros2::test {

template <class Call>
void expect_input_error(Call&& call, const std::string& part) {
  try {
    call();
    ADD_FAILURE() << "no error; expected InputError saying '" << part << "'";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(part), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace canopy::ros2::test
