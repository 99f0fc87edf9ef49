// GlTest: a fixture whose tests share one headless GL context and skip, with the reason, when none
// can be made (never pass silently without GL).
#pragma once

#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "cubeao/gl/context.h"

class GlTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() { context_ = cubeao::gl::HeadlessContext::tryCreate(&whyNot_); }
    static void TearDownTestSuite() { context_.reset(); }
    void SetUp() override {
        if (!context_) GTEST_SKIP() << "no headless GL context: " << whyNot_;
        context_->makeCurrent();
    }

    static inline std::optional<cubeao::gl::HeadlessContext> context_;
    static inline std::string whyNot_;
};

