#pragma once
// Assertions on ridge::Error messages, shared by the tests of validation (parameters, ranges,
// outputs, memory): a refusal must name the parameter and say the range.
#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

namespace ridge::test {

// The message of the ridge::Error that `f` throws; empty when it throws none.
inline std::string errorOf(const std::function<void()>& f)
{
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

// Expects every one of `phrases` in `message`.
inline void expectPhrases(const std::string& message, const std::vector<std::string>& phrases)
{
    for (const std::string& p : phrases)
        EXPECT_NE(message.find(p), std::string::npos) << "expected '" << p << "' in: " << message;
}

// Expects `f` to throw a ridge::Error whose message holds `phrase`.
inline void expectError(const std::function<void()>& f, const std::string& phrase)
{
    const std::string message = errorOf(f);
    EXPECT_NE(message.find(phrase), std::string::npos)
        << "expected '" << phrase << "' in: '" << message << "'";
}

} // namespace ridge::test
