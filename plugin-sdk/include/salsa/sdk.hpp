#pragma once
// The whole plugin SDK: include this one header. No Box2D, Qt or JSON types.
#include "salsa/behavior.hpp"
#include "salsa/contact.hpp"
#include "salsa/grid.hpp"
#include "salsa/map.hpp"
#include "salsa/metric.hpp"
#include "salsa/parameters.hpp"
#include "salsa/plugin.hpp"
#include "salsa/rng.hpp"
#include "salsa/target.hpp"
#include "salsa/vec2.hpp"
#include "salsa/wind.hpp"
#include "salsa/world.hpp"
