// SPDX-License-Identifier: MIT
#include "vsculpt/core/NearestName.h"

#include <algorithm>
#include <vector>

namespace vsculpt::core {

size_t editDistance(std::string_view a, std::string_view b) {
    // One row of the dynamic-programming table at a time.
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j)
        row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

std::string nearestName(std::string_view typed, std::span<const std::string> candidates) {
    std::string best;
    size_t bestDistance = std::max<size_t>(2, typed.size() / 3) + 1;
    for (const std::string& c : candidates) {
        if (c == typed) continue;
        const size_t d = editDistance(typed, c);
        if (d < bestDistance) {
            bestDistance = d;
            best = c;
        }
    }
    return best;
}

}  // namespace vsculpt::core
