// The floating-base branches of identifiability, identify, prepare and simulate (--floating-base;
// simulate's in command_floating_simulate.cpp): each command hands its parsed options over when
// --floating-base is given.
#pragma once

#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/program_options.hpp>

#include "core/floating/floating_model.hpp"
#include "identifiability/floating/sensor_sets.hpp"

namespace dynid::cli {

namespace po = boost::program_options;

/// --floating-base (its help ends with `does`: what the command then does), --contacts,
/// --sensors and --motion.
/// Refuses every option given that a floating-base run of the command does not read (the robot's
/// options aside).
void refuseOutside(const po::variables_map& vm, const std::set<std::string>& read,
                   const char* command);
/// --robot with a floating base; its warnings printed.
FloatingModel loadFloating(const po::variables_map& vm);
/// --sensors and --motion as the request's; usage errors naming the flag.
void readSetsAndMotion(const po::variables_map& vm, std::vector<SensorSet>& sensors,
                       std::optional<FloatingMotion>& motion);

void addFloatingOptions(po::options_description& options, const std::string& does);
/// --sole: LENGTH,WIDTH (a rectangle centred at the frame) or X1,Y1,X2,Y2,X3,Y3[,...] (corners);
/// UsageError for anything else.
std::vector<Eigen::Vector2d> soleOption(const po::variables_map& vm);
/// UsageError "--X needs --floating-base" for each of `options` given without it.
void refuseFloatingOptions(const po::variables_map& vm, std::initializer_list<const char*> options);

/// dynid identifiability --floating-base: what each sensor set determines.
int runFloatingIdentifiability(const po::variables_map& vm);
/// excite --floating-base's own options (--stance, --max-sway, ...; --floating-base, --contacts
/// and --sensors among them).
void addFloatingExciteOptions(po::options_description& options);
/// dynid excite --floating-base: a standing robot's sway designed for identification.
int runFloatingExcite(const po::variables_map& vm);
/// dynid identify --floating-base: each set's estimate on a floating dataset.
int runFloatingIdentify(const po::variables_map& vm);
/// dynid prepare --floating-base: a recording into a floating dataset.
int runFloatingPrepare(const po::variables_map& vm);
/// dynid simulate --floating-base: a floating dataset of random states.
int runFloatingSimulate(const po::variables_map& vm);

}  // namespace dynid::cli
