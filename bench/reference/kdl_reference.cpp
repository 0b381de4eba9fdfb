#include "kdl_reference.hpp"

namespace hapticd::reference {
namespace {

KDL::Frame to_kdl(const Eigen::Isometry3d& t) {
  const Eigen::Matrix3d& r = t.linear();
  return KDL::Frame(KDL::Rotation(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)),
                    KDL::Vector(t.translation().x(), t.translation().y(), t.translation().z()));
}

}  // namespace

KDL::Chain kdl_chain(const model::RobotModel& model, int frame_id) {
  KDL::Chain chain;
  for (const model::Body& b : model.bodies()) {
    chain.addSegment(KDL::Segment(b.joint_name + "_placement", KDL::Joint(KDL::Joint::Fixed), to_kdl(b.placement)));
    const KDL::Vector axis(b.axis.x(), b.axis.y(), b.axis.z());
    const KDL::Joint joint(b.joint_name, KDL::Vector::Zero(), axis,
                           b.type == model::JointType::revolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
    const Eigen::Matrix3d& i = b.inertia;
    const KDL::RigidBodyInertia inertia(b.mass, KDL::Vector(b.com.x(), b.com.y(), b.com.z()),
                                        KDL::RotationalInertia(i(0, 0), i(1, 1), i(2, 2), i(0, 1), i(0, 2), i(1, 2)));
    chain.addSegment(KDL::Segment(b.link_name, joint, KDL::Frame::Identity(), inertia));
  }
  chain.addSegment(
      KDL::Segment(model.frame(frame_id).name, KDL::Joint(KDL::Joint::Fixed), to_kdl(model.frame(frame_id).placement)));
  return chain;
}

KdlSolvers::KdlSolvers(const model::RobotModel& model, int frame_id)
    : chain(kdl_chain(model, frame_id)),
      fk(chain),
      jacobian(chain),
      jacobian_dot(chain),
      dynamics(chain, KDL::Vector(model.gravity().x(), model.gravity().y(), model.gravity().z())),
      q(chain.getNrOfJoints()),
      qd(chain.getNrOfJoints()),
      out(chain.getNrOfJoints()),
      q_qd(chain.getNrOfJoints()),
      jac(chain.getNrOfJoints()),
      mass(chain.getNrOfJoints()),
      coriolis(chain.getNrOfJoints()),
      gravity(chain.getNrOfJoints()) {
  jacobian_dot.setRepresentation(KDL::ChainJntToJacDotSolver::HYBRID);
}

}  // namespace hapticd::reference
