#pragma once
// Readers of a scene's physics blocks: materials and their pairs, the contact model, and the
// magnetic block (applied field, mutual-dipole policy, cutoff, close pairs). Used by build_scene.
#include <string>
#include <vector>

#include "core/random.hpp"
#include "scene/fidelity.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "terms/self_gravity_term.hpp"

namespace mrjam {

Material read_material(SceneNode node);
// One pair's friction and cohesion in place of the mixing rule's means.
void read_material_pair(SceneNode node, const std::vector<std::string>& names, PairTable& pairs);
// The contact block: the contact law's sub-models, and the pair damping coefficient (N s/m; 0: none).
void read_contact(SceneNode node, PhysicsSettings& ph, double& pair_damping);
// Induced coefficient (eq. 2.4), saturation cap and permanent moment of grain i.
void set_magnetic_constants(const Material& m, Particles& p, std::size_t i, Rng& rng);
// The close-pair correction's table, once the grains are placed (r_max: the largest radius).
void build_close_pair_table(System& s, double r_max);
void read_magnetic(SceneNode node, System& s, const BuildOptions& options, const FidelityTier& tier);
// A field map must cover every grain placed (refused at /magnetic/field/file, naming one that it
// misses); a domain reaching beyond it gets a warning (there the field is the map's edge value).
void check_field_map_coverage(const System& s, std::vector<std::string>& warnings);
// The self_gravity block (Barnes-Hut tree or direct summation; refused in a periodic domain).
SelfGravitySettings read_self_gravity(SceneNode node, const Domain& domain);

}  // namespace mrjam
