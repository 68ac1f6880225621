// Test helper: paths of the structures under tests/data.
#pragma once

#include <string>

namespace fdmsurf::test {

inline std::string data_path(const std::string& file) {
    return std::string(FDMSURF_TEST_DATA_DIR) + "/" + file;
}

}  // namespace fdmsurf::test
