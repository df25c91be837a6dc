// Pinocchio's forward kinematics and frame Jacobian, timed on joint vectors read from a file:
// the C++ half of bench/peers/pinocchio_compare.py (see bench/peers/README.md).
//
//   fk_jacobian MODEL TIP_LINK QS_FILE ROUNDS
//
// MODEL: the Pinocchio model built from the URDF by pinocchio.buildModelFromUrdf and saved
// with Model.saveToBinary (the pip wheels ship no urdfdom headers, so C++ cannot parse the
// URDF itself; the model is the same).
//
// QS_FILE: one joint vector per line (radians, in the URDF's joint order along the chain,
// which for the serial arms used here is Pinocchio's order too). Prints, as JSON on one
// line: the tool pose of the first joint vector (to check both libraries compute the same
// thing) and the median over ROUNDS of the time per call, nanoseconds, of
//   fk:       forwardKinematics(model, data, q) + updateFramePlacement(model, data, tip)
//   jacobian: computeFrameJacobian(model, data, q, tip, LOCAL_WORLD_ALIGNED, J)
//             (the geometric Jacobian of the tip frame's origin in world axes; it runs the
//             forward kinematics itself)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/serialization.hpp>

namespace pin = pinocchio;
using Clock = std::chrono::steady_clock;

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: fk_jacobian MODEL TIP_LINK QS_FILE ROUNDS\n");
    return 2;
  }
  pin::Model model;
  model.loadFromBinary(argv[1]);
  pin::Data data(model);
  if (!model.existFrame(argv[2])) {
    std::fprintf(stderr, "no frame %s\n", argv[2]);
    return 2;
  }
  const pin::FrameIndex tip = model.getFrameId(argv[2]);
  std::vector<Eigen::VectorXd> qs;
  std::ifstream in(argv[3]);
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    std::vector<double> v;
    for (double x; s >> x;) v.push_back(x);
    if (v.empty()) continue;
    if (static_cast<int>(v.size()) != model.nq) {
      std::fprintf(stderr, "a joint vector of %zu values, the model has nq = %d\n", v.size(), model.nq);
      return 2;
    }
    qs.push_back(Eigen::Map<Eigen::VectorXd>(v.data(), v.size()));
  }
  const int rounds = std::atoi(argv[4]);
  const size_t n = qs.size();
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, model.nv);
  double sink = 0;

  auto fk = [&](size_t i) {
    pin::forwardKinematics(model, data, qs[i]);
    pin::updateFramePlacement(model, data, tip);
    sink += data.oMf[tip].translation()[0];
  };
  auto jac = [&](size_t i) {
    J.setZero();
    pin::computeFrameJacobian(model, data, qs[i], tip, pin::LOCAL_WORLD_ALIGNED, J);
    sink += J(0, 0);
  };
  auto time_pass = [&](auto&& f) {
    auto t0 = Clock::now();
    for (size_t i = 0; i < n; ++i) f(i);
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / n;
  };
  time_pass(fk);
  time_pass(jac);
  std::vector<double> t_fk, t_jac;
  for (int r = 0; r < rounds; ++r) {
    t_fk.push_back(time_pass(fk));
    t_jac.push_back(time_pass(jac));
  }
  fk(0);
  const auto& m = data.oMf[tip];
  std::printf("{\"nq\": %d, \"poses\": %zu, \"fk_ns\": %.2f, \"jacobian_ns\": %.2f, \"tip0\": [", model.nq, n,
              median(t_fk), median(t_jac));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      std::printf("%s%.17g", (r == 0 && c == 0) ? "" : ", ", c < 3 ? m.rotation()(r, c) : m.translation()[r]);
  std::printf("], \"sink\": %g}\n", sink);
  return 0;
}
