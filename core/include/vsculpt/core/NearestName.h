// SPDX-License-Identifier: MIT
/// @file NearestName.h
/// @brief "Did you mean …?" for mistyped names (subcommands, options, config keys, actions):
/// the candidate closest to what was typed, when it is close enough to be a typo.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace vsculpt::core {

/// Levenshtein distance (insertions, deletions, substitutions; byte-wise).
size_t editDistance(std::string_view a, std::string_view b);

/// The candidate nearest to `typed` within max(2, |typed| / 3) edits (ties: the first), or ""
/// when none is that close. A candidate equal to `typed` is skipped (it was not mistyped).
std::string nearestName(std::string_view typed, std::span<const std::string> candidates);

}  // namespace vsculpt::core
