#pragma once
// Readers for the pieces a scene is made of; shared by every mode's scene file.
#include <memory>

#include "core/domain.hpp"
#include "core/format.hpp"
#include "fluid/flow_field.hpp"
#include "geometry/region.hpp"
#include "geometry/size_distribution.hpp"
#include "geometry/valve.hpp"
#include "scene/scene_node.hpp"
#include "walls.hpp"

namespace mrjam {

int read_axis(SceneNode& node, const std::string& key, std::optional<std::string> fallback);
Region read_region(SceneNode node, const Domain& domain);
SizeDistribution read_size_distribution(SceneNode node);
std::shared_ptr<FlowField> read_flow(SceneNode node, const Domain& domain);
Wall read_wall(SceneNode node, const std::vector<std::string>& material_names);
// The valve body's bore and constriction (geometry/valve.hpp), shared by `mrjam magnetics`,
// passage walls, valve flows and `mrjam jam`: every key optional, refused if impossible.
ValveGeometry read_valve(SceneNode node);
std::uint16_t material_index(SceneNode& node, const std::string& key, const std::vector<std::string>& names,
                             std::optional<std::string> fallback);

}  // namespace mrjam
