// The paper's comparison baselines that need OpenCV, in their own library
// (freespace::baselines, find_package(freespace COMPONENTS baselines)): today the rotated,
// vehicle-centred map of alignment.kind rotate.
#pragma once

namespace freespace {

// Lets every Estimator built afterwards take alignment.kind: rotate (without it, such a config
// is refused with a ConfigError). Idempotent and thread-safe.
void RegisterBaselines();

}  // namespace freespace
