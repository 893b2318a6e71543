#pragma once
// The jammed throat as a picture: the cut plane x = 0 (the y-z plane that holds the field and
// the flow), every grain the plane cuts drawn as its disc, coloured by contact cluster: the
// largest cluster blue, other clusters red, lone grains grey (as Fig. 3.11b of the source);
// the valve wall in black.
#include <filesystem>

#include "contact_clusters.hpp"
#include "geometry/valve.hpp"
#include "system.hpp"

namespace mrjam {

void write_throat_picture(const std::filesystem::path& path, const System& s, const ContactClusters& clusters,
                          const ValveGeometry& valve, int width_pixels = 900);

}  // namespace mrjam
