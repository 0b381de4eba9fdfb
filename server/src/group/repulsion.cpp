#include "group/repulsion.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/model_data.hpp"

namespace hapticd::server {

double repulsion_magnitude(const RepulsionSettings& s, double clearance, double clearance_rate) noexcept {
  if (!(s.distance_m > 0.0) || !(clearance < s.distance_m)) return 0.0;
  return std::max(0.0, s.stiffness_n_per_m * (s.distance_m - clearance) - s.damping_n_s_per_m * clearance_rate);
}

Eigen::Vector3d equivalent_handle_force(const ChainState& chain, const JointVector& torque,
                                        double max_force_n) noexcept {
  if (chain.data == nullptr || torque.size() != chain.data->frame_jacobian.cols()) return Eigen::Vector3d::Zero();
  const auto j = chain.data->frame_jacobian.topRows<3>();  // 3 x n
  // J^T F = tau in the least-squares sense: (J J^T) F = J tau, with a little regularisation near singularities.
  Eigen::Matrix3d a = j * j.transpose();
  a.diagonal().array() += 1e-12 + 1e-10 * a.trace();
  Eigen::Vector3d force = a.ldlt().solve(j * torque);
  const double norm = force.norm();
  if (!(norm <= max_force_n)) force *= norm > 0.0 ? max_force_n / norm : 0.0;  // also a non-finite result -> 0
  return force.allFinite() ? force : Eigen::Vector3d::Zero();
}

}  // namespace hapticd::server
