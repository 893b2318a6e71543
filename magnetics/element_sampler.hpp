#pragma once
// Sampling a finite-element field at arbitrary points. GetDP exports, per element, its vertex
// coordinates and the field's vertex values; B from second-order potentials is linear inside
// each element, so barycentric interpolation of those values is the solver's own field. A
// bucket grid finds the element containing a point; this is far faster than asking GetDP to
// locate every grid point itself (which took minutes for a field map).
#include <optional>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam::magnetics {

// Simplices (tetrahedra, or triangles in the plane z = 0) with one value per vertex. A value is
// a Vec3 (B) or a scalar stored in x.
struct ElementField {
    int vertices = 4;          // 4: tetrahedra; 3: triangles in z = 0
    std::vector<Vec3> points;  // vertices * elements
    std::vector<Vec3> values;  // vertices * elements
    std::size_t elements() const { return points.size() / static_cast<std::size_t>(vertices); }
    void append(const ElementField& other);
};

class ElementSampler {
public:
    explicit ElementSampler(ElementField field);
    // The interpolated value at x, or nullopt if no element contains it (within a relative
    // tolerance that admits points on faces).
    std::optional<Vec3> sample(const Vec3& x) const;

private:
    std::size_t bucket_of(int i, int j, int k) const { return (static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i; }
    bool weights(std::size_t element, const Vec3& x, double w[4]) const;

    ElementField field_;
    Vec3 lo_, cell_;
    int n_[3]{1, 1, 1};
    std::vector<std::size_t> start_, members_;  // CSR: elements per bucket
};

}  // namespace mrjam::magnetics
