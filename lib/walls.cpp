#include "walls.hpp"

#include <cmath>

namespace mrjam {

bool Wall::touch(const Vec3& x, double r, double& overlap, Vec3& n) const {
    if (kind == Kind::plane) {
        const double dist = dot(x - point, normal);
        overlap = r - dist;
        n = normal;
        return overlap > 0;
    }
    Vec3 radial = x - point;
    radial -= axis * dot(radial, axis);
    const double rho = norm(radial);
    if (inside) {
        overlap = rho + r - radius;
        if (overlap <= 0) return false;
        // On the axis itself the direction is arbitrary; any radial unit vector is right there.
        n = rho > 0 ? radial * (-1.0 / rho) : Vec3{1, 0, 0};
    } else {
        overlap = radius + r - rho;
        if (overlap <= 0) return false;
        n = rho > 0 ? radial * (1.0 / rho) : Vec3{1, 0, 0};
    }
    return true;
}

}  // namespace mrjam
