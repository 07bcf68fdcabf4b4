#pragma once
// The core's test models, one file each, and their list in file order: a new model is its file, a line
// here and one in the list.
#include "salsa/core/experiments/test_models.hpp"

namespace salsa::models {

TestModel fleet();     ///< groups, batteries and what fails: who is alive, the energy drawn
TestModel failures();  ///< the "failures" section: random failures of drones and cameras
TestModel comm();      ///< the "comm" section: messages between drones
TestModel wind();      ///< the "wind" section: moving air
TestModel noise();     ///< the drones' sensor noise: its false detections

/// Every core model, in the order of their sections in config.json and of their columns in the data files.
inline std::vector<TestModel> core_models() { return {fleet(), failures(), comm(), wind(), noise()}; }

}  // namespace salsa::models
