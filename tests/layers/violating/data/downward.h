#pragma once
#include "geometry/upward.h"
