#pragma once
// The core's test models, one file each; test_models.cpp lists them in file order.
#include "salsa/core/experiments/test_models.hpp"

namespace salsa::models {

TestModel fleet();     ///< groups, batteries and what fails: who is alive, the energy drawn
TestModel failures();  ///< the "failures" section: random failures of drones and cameras
TestModel comm();      ///< the "comm" section: messages between drones
TestModel wind();      ///< the "wind" section: moving air
TestModel noise();     ///< the drones' sensor noise: its false detections

}  // namespace salsa::models
