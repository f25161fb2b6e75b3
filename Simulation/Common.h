// The basic numeric types (Real, Vector3r, Matrix3r, Quaternionr, Index) for the simulation
// layers; they are defined in Utilities/Types.h, which the utilities include directly.
#pragma once
#include "Utilities/Types.h"
