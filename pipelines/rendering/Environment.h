#pragma once
// The distant surroundings `synth` draws behind the scene. A real photograph always shows
// something behind an object, and what it shows depends on the direction of the viewing
// ray: a point that is not on the scene's surface sees different background from different
// cameras. A uniform void instead would be perfectly photo-consistent from every view, and
// a likelihood would happily grow surface into it (a column taller than the truth, say).

#include <Eigen/Core>

namespace vkr {

// Encoded RGB colour of the environment in world direction `direction` (need not be unit):
// multi-scale value noise on the sphere for brightness and hue.
Eigen::Vector3f EnvironmentColour(const Eigen::Vector3d& direction);

}  // namespace vkr
