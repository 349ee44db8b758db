#include "identify/stream_regressor.hpp"

#include <cmath>
#include <cstddef>

#include "core/simd_clones.hpp"
#include "core/sincos.hpp"
#include "massid/core/regressor.hpp"

namespace massid::detail {

namespace {

using Step = StreamRegressor::Step;
using Col = StreamRegressor::Col;

// The batch kernel (StreamRegressor::compute): every loop runs over the m
// samples r, so the compiler vectorises it across samples.
MASSID_AVX2_CLONES
void moment_rows(const Step* steps, int num_steps, const Col* cols, int K, int cap, double* pose,
                 double* angle, double* sn, double* cs, int m, const double* q, const double* g,
                 int ld_in, double* const out[3], int ld_out) {
  auto P = [&](int link) { return pose + static_cast<std::ptrdiff_t>(link) * 12 * cap; };
  for (int si = 0; si < num_steps; ++si) {
    const Step& s = steps[si];
    if (s.constant) continue;
    const double* __restrict Rp = P(s.parent);
    double* __restrict M = P(si + 1);
    // M = R_parent Ro, pos = p_parent + R_parent to.
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) {
        double* __restrict y = M + (3 * c + i) * cap;
        const double* __restrict x0 = Rp + i * cap;
        const double* __restrict x1 = Rp + (3 + i) * cap;
        const double* __restrict x2 = Rp + (6 + i) * cap;
        if (s.Ro_identity) {
          const double* __restrict x = Rp + (3 * c + i) * cap;
          for (int r = 0; r < m; ++r) y[r] = x[r];
        } else {
          const double a0 = s.Ro(0, c), a1 = s.Ro(1, c), a2 = s.Ro(2, c);
          for (int r = 0; r < m; ++r) y[r] = (x0[r] * a0 + x1[r] * a1) + x2[r] * a2;
        }
      }
    for (int i = 0; i < 3; ++i) {
      double* __restrict y = M + (9 + i) * cap;
      const double* __restrict pp = Rp + (9 + i) * cap;
      const double* __restrict x0 = Rp + i * cap;
      const double* __restrict x1 = Rp + (3 + i) * cap;
      const double* __restrict x2 = Rp + (6 + i) * cap;
      if (s.to_zero) {
        for (int r = 0; r < m; ++r) y[r] = pp[r];
      } else {
        const double t0 = s.to[0], t1 = s.to[1], t2 = s.to[2];
        for (int r = 0; r < m; ++r) y[r] = pp[r] + ((x0[r] * t0 + x1[r] * t1) + x2[r] * t2);
      }
    }
    const double* __restrict qj = q + static_cast<std::ptrdiff_t>(s.joint) * ld_in;
    if (s.type == JointType::Revolute) {
      const double sign = s.axis_sign;
      const double scale = s.joint_scale, offset = s.joint_offset;  // 1, 0 unless a mimic
      for (int r = 0; r < m; ++r) angle[r] = sign * (scale * qj[r] + offset);
      const int even = (m + 1) / 2 * 2;
      if (even > m) angle[m] = 0.0;
      sincos_many(angle, sn, cs, even);
      if (s.axis_kind > 0) {
        // M <- M Rot(axis, angle): columns u, v turn in their plane (u, v =
        // the two axes other than the joint's, in cyclic order).
        const int u = s.axis_kind % 3, v = (s.axis_kind + 1) % 3;
        for (int i = 0; i < 3; ++i) {
          double* __restrict cu = M + (3 * u + i) * cap;
          double* __restrict cv = M + (3 * v + i) * cap;
          for (int r = 0; r < m; ++r) {
            const double a = cu[r], b = cv[r];
            cu[r] = cs[r] * a + sn[r] * b;
            cv[r] = cs[r] * b - sn[r] * a;
          }
        }
      } else {
        // Rodrigues: Rot = c I + s [a]x + (1 - c) a a^T, per sample (plain
        // scalar code: the same operations in every copy of this function).
        const double ax[3] = {s.axis[0], s.axis[1], s.axis[2]};
        double Kx[3][3] = {{0, -ax[2], ax[1]}, {ax[2], 0, -ax[0]}, {-ax[1], ax[0], 0}};
        for (int r = 0; r < m; ++r) {
          double rot[3][3], Mr[3][3];
          for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c)
              rot[k][c] =
                  ((k == c ? cs[r] : 0.0) + sn[r] * Kx[k][c]) + (1.0 - cs[r]) * ax[k] * ax[c];
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) Mr[i][c] = M[(3 * c + i) * cap + r];
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c)
              M[(3 * c + i) * cap + r] =
                  (Mr[i][0] * rot[0][c] + Mr[i][1] * rot[1][c]) + Mr[i][2] * rot[2][c];
        }
      }
    } else if (s.type == JointType::Prismatic) {
      const double a0 = s.axis[0], a1 = s.axis[1], a2 = s.axis[2];
      for (int i = 0; i < 3; ++i) {
        double* __restrict y = M + (9 + i) * cap;
        const double* __restrict x0 = M + i * cap;
        const double* __restrict x1 = M + (3 + i) * cap;
        const double* __restrict x2 = M + (6 + i) * cap;
        const double scale = s.joint_scale, offset = s.joint_offset;
        for (int r = 0; r < m; ++r)
          y[r] += ((x0[r] * a0 + x1[r] * a1) + x2[r] * a2) * (scale * qj[r] + offset);
      }
    }
  }
  // Moment rows v x g of each unknown, v = p_l or R_l e_k.
  const double* __restrict gx = g;
  const double* __restrict gy = g + ld_in;
  const double* __restrict gz = g + 2 * static_cast<std::ptrdiff_t>(ld_in);
  for (int k = 0; k < K; ++k) {
    const Col& c = cols[k];
    const double* v = P(c.link) + (c.kind == kMass ? 9 : 3 * (c.kind - 1)) * cap;
    const double* __restrict vx = v;
    const double* __restrict vy = v + cap;
    const double* __restrict vz = v + 2 * cap;
    double* __restrict ox = out[0] + static_cast<std::ptrdiff_t>(k) * ld_out;
    double* __restrict oy = out[1] + static_cast<std::ptrdiff_t>(k) * ld_out;
    double* __restrict oz = out[2] + static_cast<std::ptrdiff_t>(k) * ld_out;
    for (int r = 0; r < m; ++r) {
      ox[r] = vy[r] * gz[r] - vz[r] * gy[r];
      oy[r] = vz[r] * gx[r] - vx[r] * gz[r];
      oz[r] = vx[r] * gy[r] - vy[r] * gx[r];
    }
  }
}

}  // namespace

StreamRegressor::StreamRegressor(const Model& model, const BaseParameters& base, int capacity)
    : capacity_((capacity + 1) / 2 * 2) {
  const int cap = capacity_;
  pose_.assign(static_cast<std::size_t>(model.num_links()) * 12 * cap, 0.0);
  angle_.assign(cap, 0.0);
  sin_.assign(cap, 0.0);
  cos_.assign(cap, 1.0);
  std::vector<Eigen::Matrix3d> R(model.links.size(), Eigen::Matrix3d::Identity());
  std::vector<Eigen::Vector3d> p(model.links.size(), Eigen::Vector3d::Zero());
  for (int l = 1; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    Step s;
    s.parent = link.parent;
    s.Ro = link.origin.linear();
    s.to = link.origin.translation();
    s.Ro_identity = s.Ro == Eigen::Matrix3d::Identity();
    s.to_zero = s.to == Eigen::Vector3d::Zero();
    s.type = link.type;
    s.axis = link.axis;
    s.joint = link.joint_index;
    s.joint_scale = link.joint_scale;
    s.joint_offset = link.joint_offset;
    for (int i = 0; i < 3; ++i)
      if (std::abs(link.axis[i]) == 1.0 && link.axis.squaredNorm() == 1.0) {
        s.axis_kind = 1 + i;
        s.axis_sign = link.axis[i];
      }
    s.constant = s.type == JointType::Fixed && (s.parent == 0 || steps_[s.parent - 1].constant);
    if (s.constant) {
      R[l] = R[s.parent] * s.Ro;
      p[l] = p[s.parent] + R[s.parent] * s.to;
    }
    steps_.push_back(s);
  }
  // The sensor link and the links fixed to it: the same pose for every sample.
  for (int l = 0; l < model.num_links(); ++l) {
    if (l > 0 && !steps_[l - 1].constant) continue;
    double* P = pose_.data() + static_cast<std::size_t>(l) * 12 * cap;
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i)
        for (int r = 0; r < cap; ++r) P[(3 * c + i) * cap + r] = R[l](i, c);
    for (int i = 0; i < 3; ++i)
      for (int r = 0; r < cap; ++r) P[(9 + i) * cap + r] = p[l][i];
  }
  for (int i = 0; i < base.num_mass(); ++i) {
    if (i == base.total_mass) continue;
    const int c = base.column[i];
    cols_.push_back({c / kParamsPerLink, c % kParamsPerLink});
    unknown_.push_back(i);
  }
}

void StreamRegressor::compute(int m, const double* q, const double* g, int ld_in,
                              double* const out[3], int ld_out) {
  moment_rows(steps_.data(), static_cast<int>(steps_.size()), cols_.data(), size(), capacity_,
              pose_.data(), angle_.data(), sin_.data(), cos_.data(), m, q, g, ld_in, out, ld_out);
}

}  // namespace massid::detail
