/// @file scene.h
/// Scenes: read a file into data (scene_reader.h), replace what the caller overrides
/// (scene_overrides.h), then build the simulation (scene_builder.h).
#pragma once

#include "cloth_sim/core/io/scene_builder.h"
#include "cloth_sim/core/io/scene_limits.h"
#include "cloth_sim/core/io/scene_overrides.h"
#include "cloth_sim/core/io/scene_reader.h"
