// The OpenCL device of the tests that need one (opencl_test.cpp, work_shape_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include "freespace/errors.hpp"
#include "opencl/runtime.hpp"

// The device an unfiltered choice takes, or a skip when there is none.
#define FREESPACE_DEVICE_OR_SKIP(var)                        \
  opencl::DeviceChoice var;                                  \
  try {                                                      \
    var = opencl::ChooseDevice(BackendConfig{});             \
  } catch (const BackendError& e) {                          \
    GTEST_SKIP() << "no usable OpenCL device: " << e.what(); \
  }
