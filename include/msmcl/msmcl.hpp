// Umbrella header: everything of the C++ API.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/device_math.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/types.hpp>
#include <msmcl/version.hpp>
