#pragma once
// A geometry header that reaches up into data/: the layer check must refuse it.
#include "data/measurements.h"
