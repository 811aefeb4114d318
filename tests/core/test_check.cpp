// CAVESIM_CHECK: silent when the condition holds, InternalError naming file:line otherwise.
#include <gtest/gtest.h>

#include <string>

#include "core/check.h"
#include "core/error.h"

namespace cavesim {
namespace {

TEST(Check, PassesSilentlyAndDoesNotBuildTheMessage) {
    int built = 0;
    auto message = [&] {
        ++built;
        return std::string("never");
    };
    EXPECT_NO_THROW(CAVESIM_CHECK(1 + 1 == 2, message()));
    EXPECT_EQ(built, 0);
}

TEST(Check, ThrowsInternalErrorNamingFileLineConditionAndMessage) {
    const int value = 3;
    int line = 0;
    try {
        line = __LINE__ + 1;
        CAVESIM_CHECK(value < 2, "value must be below 2, got " + std::to_string(value));
        FAIL() << "no exception";
    } catch (const InternalError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("internal error"), std::string::npos) << what;
        EXPECT_NE(what.find("tests/core/test_check.cpp:" + std::to_string(line)), std::string::npos) << what;
        EXPECT_NE(what.find("value < 2"), std::string::npos) << what;
        EXPECT_NE(what.find("value must be below 2, got 3"), std::string::npos) << what;
    }
}

TEST(Check, InternalErrorIsACavesimErrorButNotInputError) {
    EXPECT_THROW(CAVESIM_CHECK(false, "x"), Error);
    EXPECT_THROW(CAVESIM_CHECK(false, "x"), std::runtime_error);
    bool asInput = false;
    try {
        CAVESIM_CHECK(false, "x");
    } catch (const InputError&) {
        asInput = true;
    } catch (const Error&) {
    }
    EXPECT_FALSE(asInput);
}

TEST(Check, WorksAsASingleStatement) {
    // The macro is one statement: safe in an unbraced if/else.
    int n = 0;
    if (n == 0)
        CAVESIM_CHECK(true, "fine");
    else
        n = 1;
    EXPECT_EQ(n, 0);
}

}  // namespace
}  // namespace cavesim
