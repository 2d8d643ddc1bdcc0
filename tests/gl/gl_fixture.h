// One headless GL context for a whole test executable (creating one per test is slow on
// llvmpipe). Tests that need GL derive from GlTest.
#pragma once

#include "gpu/context.h"

#include <gtest/gtest.h>

#include <memory>

namespace veil::test {

class GlTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (!context_) context_ = std::make_unique<gpu::HeadlessContext>();
    }
    static const gpu::ContextInfo& info() { return context_->info(); }
    static inline std::unique_ptr<gpu::HeadlessContext> context_;
};

// Magnum's MAGNUM_VERIFY_NO_GL_ERROR(): fail the test on any pending GL error.
#define VEIL_EXPECT_NO_GL_ERROR() EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR))

} // namespace veil::test
