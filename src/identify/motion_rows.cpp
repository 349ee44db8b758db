#include "identify/motion_rows.hpp"

#include "massid/core/parameters.hpp"

namespace massid::detail {

MotionRows::MotionRows(const Model& model, const BaseParameters& base)
    : model_(&model),
      first_(model.num_links(), 0),
      inertia_(model.num_links(), 0),
      data_(model),
      frames_(model.num_links()),
      zero_(Eigen::VectorXd::Zero(model.num_joints())) {
  const int P = base.layout.per_link();
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    cols_.push_back({c / P, c % P});
    if (c % P >= kMx) first_[c / P] = 1;
    if (c % P >= kIxx) inertia_[c / P] = 1;
  }
}

void MotionRows::compute(const double* q, const double* qd, const double* qdd, const double* g,
                         const double* sensor, double* out) {
  using Eigen::Vector3d;
  const int nj = model_->num_joints();
  using Map = Eigen::Map<const Eigen::VectorXd>;
  FrameMotion sm;
  if (sensor) {
    sm.omega = Vector3d(sensor[0], sensor[1], sensor[2]);
    sm.omega_dot = Vector3d(sensor[3], sensor[4], sensor[5]);
    sm.accel = Vector3d(sensor[6], sensor[7], sensor[8]);
  }
  forward_kinematics(*model_, data_, Map(q, nj), qd ? Map(qd, nj) : Map(zero_.data(), nj),
                     qdd ? Map(qdd, nj) : Map(zero_.data(), nj), Vector3d(g[0], g[1], g[2]), sm);
  const int L = model_->num_links();
  for (int l = 0; l < L; ++l) {
    const Eigen::Matrix3d& R = data_.rotation[l];
    Frame& f = frames_[l];
    f.a = R * data_.accel[l];
    if (first_[l] || inertia_[l]) {
      f.w = R * data_.omega[l];
      f.dw = R * data_.omega_dot[l];
      for (int k = 0; k < 3; ++k) f.wr[k] = f.w.cross(R.col(k));
    }
  }
  const Vector3d a0 = frames_[0].a;
  for (size_t i = 0; i < cols_.size(); ++i) {
    const Col& c = cols_[i];
    const Frame& f = frames_[c.link];
    const Eigen::Matrix3d& R = data_.rotation[c.link];
    const Vector3d& p = data_.position[c.link];
    Vector3d F, M;
    switch (c.kind) {
      case kMass:
        F = -f.a;
        M = p.cross(F);
        if (c.link != 0) F += a0;  // m_l - m_sensor
        break;
      case kMx:
      case kMy:
      case kMz: {
        const int k = c.kind - kMx;
        const auto r = R.col(k);
        F = -(f.dw.cross(r) + f.w.cross(f.wr[k]));
        M = p.cross(F) - r.cross(f.a);
        break;
      }
      default: {
        // m = -(R L(u) + w x R L(v)), u = dw_l, v = w_l: pairs (k, m) of columns of R.
        static constexpr int kPair[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
        const int k = kPair[c.kind - kIxx][0], m = kPair[c.kind - kIxx][1];
        const Vector3d& u = data_.omega_dot[c.link];
        const Vector3d& v = data_.omega[c.link];
        F.setZero();
        if (k == m)
          M = -(R.col(k) * u[k] + f.wr[k] * v[k]);
        else
          M = -((R.col(k) * u[m] + R.col(m) * u[k]) + (f.wr[k] * v[m] + f.wr[m] * v[k]));
        break;
      }
    }
    double* o = out + 6 * i;
    for (int a = 0; a < 3; ++a) {
      o[a] = F[a];
      o[3 + a] = M[a];
    }
  }
}

}  // namespace massid::detail
