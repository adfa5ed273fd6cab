// The floating-base branches of identifiability, identify, prepare and simulate (--floating-base),
// in one room: each command hands its parsed options over when --floating-base is given.
#pragma once

#include <initializer_list>
#include <string>

#include <boost/program_options.hpp>

namespace dynid::cli {

namespace po = boost::program_options;

/// --floating-base (its help ends with `does`: what the command then does), --contacts,
/// --sensors and --motion.
void addFloatingOptions(po::options_description& options, const std::string& does);
/// UsageError "--X needs --floating-base" for each of `options` given without it.
void refuseFloatingOptions(const po::variables_map& vm, std::initializer_list<const char*> options);

/// dynid identifiability --floating-base: what each sensor set determines.
int runFloatingIdentifiability(const po::variables_map& vm);
/// dynid identify --floating-base: each set's estimate on a floating dataset.
int runFloatingIdentify(const po::variables_map& vm);
/// dynid prepare --floating-base: a recording into a floating dataset.
int runFloatingPrepare(const po::variables_map& vm);
/// dynid simulate --floating-base: a floating dataset of random states.
int runFloatingSimulate(const po::variables_map& vm);

}  // namespace dynid::cli
