#pragma once
// artemis dataset info FILE.bag: what a ROS 1 bag holds (topics, message types, counts, rates,
// duration) and which topics a run would read, and why.

#include <string>

#include "artemis/datasets/bag_topics.hpp"

namespace artemis::cli {

// Prints the bag's summary (a table, or one JSON object); returns the exit code.
int runBagInfo(const std::string& bag, const datasets::BagTopicRequest& request, bool json);

}  // namespace artemis::cli
