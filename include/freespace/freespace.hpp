// Everything a user of the engine includes.
#pragma once

#include "freespace/config.hpp"
#include "freespace/devices.hpp"
#include "freespace/errors.hpp"
#include "freespace/estimator.hpp"
#include "freespace/io.hpp"
#include "freespace/log.hpp"
#include "freespace/map_io.hpp"
#include "freespace/result.hpp"
#include "freespace/scan.hpp"
#include "freespace/types.hpp"
#include "freespace/version.hpp"
