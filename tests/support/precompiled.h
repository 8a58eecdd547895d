#pragma once
// The test executables' precompiled header (tests/CMakeLists.txt): GoogleTest and the standard
// and JSON headers most tests include. Parsing them was about half of a test file's compile
// time; every test file still includes what it uses (the library-only and fuzz builds, which
// have no precompiled header, compile the sources the tests share).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>
