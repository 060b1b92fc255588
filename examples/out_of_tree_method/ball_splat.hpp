// A method of one's own: register it, then run pcrt's commands with it (main.cpp).
#pragma once

#include "methods/method.hpp"

void register_ball_splat(pcrt::MethodRegistry& registry);
