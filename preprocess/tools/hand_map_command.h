#pragma once
// `hfts-preprocess --hand ROBOT.json -o DIR`: the hand reachability map.

#include <string>

namespace hfts::preprocess {

/// Builds the hand map of the robot and writes DIR/<robot name>_hand_map.h5;
/// prints what it built. Returns the exit code; throws on errors.
int handMapCommand(const std::string& robotConfig, const std::string& outDir,
                   unsigned long long seed);

}  // namespace hfts::preprocess
