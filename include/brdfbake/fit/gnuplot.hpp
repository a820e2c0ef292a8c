#pragma once
/// @file
/// Charts moved to core (core/gnuplot.hpp); this header stays while callers still include it.

#include <brdfbake/core/gnuplot.hpp>
