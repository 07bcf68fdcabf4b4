// Box2D 2.4 times each step, its broad phase and every island it solves for b2World::GetProfile(), with
// a gettimeofday per timer call: a few per island, and with drones apart every drone is an island of
// its own. salsa never reads the profile, and these calls were 15 % of a 1,000-drone step (perf). Its
// calls go through the PLT, so these definitions take their place; a profile reads 0 ms. Nothing else
// in Box2D reads a timer.
#include <box2d/b2_timer.h>

b2Timer::b2Timer() = default;
void b2Timer::Reset() {}
float b2Timer::GetMilliseconds() const { return 0.0f; }
