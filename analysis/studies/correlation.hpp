// Statistics for comparing errors: correlation coefficients.
#pragma once

#include <vector>

namespace dynid {

/// Pearson's correlation coefficient of x and y (equal sizes); NaN with fewer than 3 pairs or a
/// constant series.
double pearson(const std::vector<double>& x, const std::vector<double>& y);
/// Spearman's rank correlation: Pearson's r of the ranks, ties given their average rank.
double spearman(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace dynid
