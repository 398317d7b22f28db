// The sub-commands that take spatial models (check, info, sweep --solver numeric, draw); main.cpp
// and cmd_draw.cpp send a description with `dimension: spatial` here.
#pragma once

#include "cli/command.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::cli {

int run_spatial_check(const Args& args);
int run_spatial_info(const Args& args);
int run_spatial_sweep(const Args& args);
int run_spatial_draw(const Args& args);

}  // namespace mechgen::cli
