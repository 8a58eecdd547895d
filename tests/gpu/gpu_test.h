#pragma once
// Fixture for tests that need GL: a HeadlessContext current for the whole test. CI machines
// have Mesa llvmpipe, so failing to create one is a failure, never a skip.
#include "ridge/core/error.h"
#include "ridge/gpu/context.h"

#include <gtest/gtest.h>

#include <memory>

namespace ridge::gpu::test {

class GpuTest : public ::testing::Test {
  protected:
    void SetUp() override
    {
        try {
            context_ = HeadlessContext::create();
        } catch (const Error& e) {
            FAIL() << "no headless GL 4.5 context: " << e.what();
        }
    }

    // Objects made in the test body die before TearDown destroys the context, as GL requires.
    std::unique_ptr<HeadlessContext> context_;
};

} // namespace ridge::gpu::test
