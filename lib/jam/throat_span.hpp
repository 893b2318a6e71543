#pragma once
// Whether the largest contact cluster is an arch across the throat: it touches the
// constriction's wall on both sides of the gap along the field (y), as in the source's Fig. 3.11b.
#include "contact_clusters.hpp"
#include "geometry/valve.hpp"
#include "system.hpp"
#include "walls.hpp"

namespace mrjam {

// Circular orifice: a grain of the cluster touches the wall (taper or throat) at y > 0 and one at
// y < 0. Slot: the cluster touches the faces across the gap, contacts whose normal is mostly
// along -y (the upper face) and +y (the lower); the narrow side faces (x) do not count, since a
// cluster from one of them to the other lies across the flow without closing the gap.
bool cluster_spans_throat(const System& s, const ContactClusters& clusters, const ValveGeometry& valve,
                          const Wall& wall);

}  // namespace mrjam
