// A row of dynid study's table with the same errors on both datasets (the conclusion tests).
#pragma once

#include <string>

#include "analysis/studies/log_study.hpp"

namespace dynid::test {

inline LogStudyRow studyRow(const std::string& key, double torque, double gc, bool consistent) {
  LogStudyRow r;
  r.key = key;
  r.torque_train = r.torque_test = torque;
  r.gc_train = r.gc_test = gc;
  r.consistent = consistent;
  return r;
}

}  // namespace dynid::test
