// Trajectory datasets as CSV: header t,q1..qn,dq1..dqn,ddq1..ddqn,tau1..taun, one sample per row,
// SI units (s, rad, rad/s, rad/s^2, N m), comma-separated, '.' as the decimal point.
#pragma once

#include <string>

#include "core/trajectory.hpp"

namespace dynid {

/// The header line (without newline) for n joints.
std::string datasetHeader(int num_joints);

/// Writes the trajectory atomically (io.hpp), numbers in shortest round-trip form, so reading the
/// file back gives exactly the same doubles. Throws Error when the file cannot be written,
/// InputError when the trajectory's matrices disagree in size.
void writeDatasetCsv(const std::string& path, const Trajectory& trajectory);

/// Reads a dataset. Checks the header (names the column that differs), that every row has
/// 1 + 4n fields, that every field is a finite number, and that time strictly increases; when
/// expected_joints >= 0, also that n matches it. Throws ParseError(file, line, column, ...) naming
/// the line and column at fault, Error when the file cannot be read, and InputError naming the file
/// before allocating when the file or its samples would not fit in memory (core/memory.hpp).
Trajectory readDatasetCsv(const std::string& path, int expected_joints = -1);

}  // namespace dynid
