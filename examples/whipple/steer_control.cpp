// Stabilizing the Whipple bicycle below its weave speed with a steer torque, an input of the scene.
//
// At v = 3 m/s the benchmark bicycle (Meijaard et al. 2007; examples/whipple/whipple_bicycle.toml)
// is unstable: its weave mode grows. This application
//   1. linearizes the scene at upright straight running, v = 3 (nhc::linearize), and takes the
//      lean and steer block of (A, B): states s = (phi, phi', delta, delta'), input Tdelta;
//   2. designs a state feedback Tdelta = -K s by LQR: K = R^-1 B' P with P the stabilizing
//      solution of A'P + PA - P B R^-1 B' P + Q = 0, from the stable invariant subspace of the
//      Hamiltonian [A, -B R^-1 B'; -Q, -A'] (Laub's method, with Eigen's eigenvectors);
//   3. runs the nonlinear bicycle (nhc::jit) from a lean of 0.05 rad, once without the controller
//      and once with it (Integrator::set_inputs: the law evaluated at every residual call);
//   4. writes DIR/steer_control.csv (t, lean and steer of both runs, the steer torque) and, where
//      gnuplot is installed, DIR/steer_control.svg and .png.
// Exit 0 when the controlled lean stays within 0.05 rad over 10 s while the free bicycle's lean
// exceeds 0.5 rad (its run stops at a lean of 1 rad, a fall); 1 otherwise, saying which; 2 for
// bad arguments.
//
// Usage: steer_control SCENE DIR
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/tools/gnuplot.hpp"
#include "nhc/linearize.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/runtime/runtime.hpp"

namespace {

constexpr double kSpeed = 3.0, kLean0 = 0.05, kDuration = 10.0;

/// The stabilizing solution of the continuous algebraic Riccati equation (Laub 1979).
Eigen::MatrixXd riccati(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& R) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd H(2 * n, 2 * n);
  H << A, -B * R.inverse() * B.transpose(), -Q, -A.transpose();
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(H);
  Eigen::MatrixXcd stable(2 * n, n);
  Eigen::Index found = 0;
  for (Eigen::Index k = 0; k < 2 * n && found < n; ++k)
    if (eigen.eigenvalues()(k).real() < 0) stable.col(found++) = eigen.eigenvectors().col(k);
  if (found != n) throw std::runtime_error("the Hamiltonian has eigenvalues on the imaginary axis");
  const Eigen::MatrixXcd P = stable.bottomRows(n) * stable.topRows(n).inverse();
  return P.real();
}

struct Motion {
  std::vector<double> t, lean, steer, torque;
  bool stopped = false;
  std::string why;
};

Motion run(const nhc::runtime::Model& model, const nhc::Scene& scene, const Eigen::RowVectorXd* gain,
           const std::vector<int>& s_states) {
  nhc::runtime::IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  nhc::runtime::Integrator integrator(model, {}, options);
  const int steer_torque = model.input_index("Tdelta");
  if (gain)  // Tdelta = -K s at every residual call, from the states the generated code holds
    integrator.set_inputs([gain, s_states, steer_torque](double, const double* y, double* u) {
      double torque = 0;
      for (std::size_t k = 0; k < s_states.size(); ++k)
        torque -= (*gain)(static_cast<Eigen::Index>(k)) * y[s_states[k]];
      u[0] = 0;  // Tphi: no lean torque
      u[steer_torque] = torque;
    });
  // A lean of 1 rad is a fall (the pedals and handlebar reach the ground well before): stop there.
  const int lean = s_states[0];
  integrator.add_event(
      {"fallen", [lean](double, const double* y, const double*) { return 1.0 - std::abs(y[lean]); }, true});
  Motion m;
  try {
    integrator.initialize(nhc::runtime::initial_state_from(model, scene.initial.t0, scene.initial.values), 0.02);
    integrator.integrate(nhc::runtime::output_times(0.0, kDuration, 500), [&](const nhc::runtime::Sample& s) {
      m.t.push_back(s.t);
      m.lean.push_back(s.y[static_cast<std::size_t>(s_states[0])]);
      m.steer.push_back(s.y[static_cast<std::size_t>(s_states[2])]);
      m.torque.push_back(s.u[static_cast<std::size_t>(steer_torque)]);
    });
    if (!integrator.events().empty()) {
      m.stopped = true;
      m.why = "fallen: the lean reached 1 rad";
    }
  } catch (const nhc::base::SolverError& e) {
    m.stopped = true;
    m.why = e.what();
  }
  return m;
}

double largest_lean(const Motion& m) {
  double worst = 0;
  for (double lean : m.lean) worst = std::max(worst, std::abs(lean));
  return worst;
}

void write_csv(const std::filesystem::path& path, const Motion& free, const Motion& controlled) {
  const auto n = [](double v) { return nhc::base::number_text(v, 10); };
  std::ofstream out(path);
  out << "t,lean_free,steer_free,lean_controlled,steer_controlled,steer_torque\n";
  for (std::size_t k = 0; k < controlled.t.size(); ++k) {
    out << n(controlled.t[k]);
    if (k < free.t.size() && free.t[k] == controlled.t[k])
      out << "," << n(free.lean[k]) << "," << n(free.steer[k]);  // not the fall's own time
    else out << ",,";
    out << "," << n(controlled.lean[k]) << "," << n(controlled.steer[k]) << "," << n(controlled.torque[k]) << "\n";
  }
}

void plot(const std::filesystem::path& dir) {
  if (const auto missing = nhc::tools::gnuplot_missing()) {
    std::cout << *missing << ": no picture (the CSV has the data)\n";
    return;
  }
  const std::string script = R"(set datafile separator ','
set key autotitle columnhead outside bottom horizontal
set xlabel 't (s)'
set ylabel 'angle (rad)'
set yrange [-1.05:1.05]
set grid
set title 'Whipple bicycle at 3 m/s from a lean of 0.05 rad: free and with LQR steer torque'
do for [format in 'svg png'] {
  if (format eq 'svg') { set terminal svg size 900,500 } else { set terminal pngcairo size 900,500 }
  set output 'steer_control.'.format
  plot 'steer_control.csv' using 1:2 with lines lw 2 title 'lean, free', \
       '' using 1:3 with lines dt 2 title 'steer, free', \
       '' using 1:4 with lines lw 2 title 'lean, controlled', \
       '' using 1:5 with lines dt 2 title 'steer, controlled'
}
)";
  std::ofstream(dir / "steer_control.gp") << script;
  // nhc's gnuplot runner: the directory and the script's name are arguments, never a shell's text.
  std::string messages;
  if (nhc::tools::run_gnuplot(dir, {"steer_control.gp"}, messages) != 0)
    std::cout << "gnuplot failed: no picture\n" << messages;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: steer_control SCENE DIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[2];
  std::filesystem::create_directories(dir);
  try {
    nhc::Scene scene = nhc::load_scene(argv[1]);
    const auto v = scene.jet->parameter_index("v");
    if (!v || !scene.jet->input_index("Tdelta"))
      throw std::runtime_error("the scene has no parameter v or input Tdelta");
    scene.parameter_values[static_cast<std::size_t>(*v)] = kSpeed;
    reevaluate_initial_expressions(scene);  // the wheel rates follow v
    scene.initial.values["phi"] = {kLean0, 0.0};

    // 1. (A, B) at upright straight running; the lean and steer block.
    const nhc::Linearization lin = nhc::linearize(scene, nhc::ModelKind::chetaev, {{"phi", 0.0}, {"phi'", 0.0}});
    const std::vector<std::string> names{"phi", "phi'", "delta", "delta'"};
    std::vector<Eigen::Index> rows;
    for (const std::string& name : names) {
      const auto at = std::find(lin.states.begin(), lin.states.end(), name);
      if (at == lin.states.end())
        throw std::runtime_error("state " + name + " is not among the linearization's states");
      rows.push_back(static_cast<Eigen::Index>(at - lin.states.begin()));
    }
    const auto steer_column =
        static_cast<Eigen::Index>(std::find(lin.inputs.begin(), lin.inputs.end(), "Tdelta") - lin.inputs.begin());
    Eigen::MatrixXd A(4, 4), B(4, 1);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) A(i, j) = lin.A(rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(j)]);
      B(i, 0) = lin.B(rows[static_cast<std::size_t>(i)], steer_column);
    }
    std::cout << "open loop at v = " << kSpeed << " m/s, eigenvalues of the lean-steer block:\n"
              << Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues().transpose() << "\n";

    // 2. LQR.
    const Eigen::Vector4d weights(1e4, 1.0, 1.0, 1.0);  // lean most: it never exceeds its start
    const Eigen::MatrixXd P = riccati(A, B, weights.asDiagonal(), Eigen::MatrixXd::Identity(1, 1));
    const Eigen::RowVectorXd K = B.transpose() * P;
    std::cout << "LQR gain K (Tdelta = -K [phi, phi', delta, delta']): " << K << "\n"
              << "closed-loop eigenvalues: " << Eigen::EigenSolver<Eigen::MatrixXd>(A - B * K).eigenvalues().transpose()
              << "\n";

    // 3. The nonlinear bicycle, free and controlled.
    const nhc::jit::LoadedModel built = nhc::jit::build(scene, nhc::ModelKind::chetaev);
    const nhc::runtime::Model& model = built.model();
    const int phi = 3, delta = 5;  // coordinate indices in the scene
    const std::vector<int> s_states{model.state_index(phi, 0), model.state_index(phi, 1), model.state_index(delta, 0),
                                    model.state_index(delta, 1)};
    const Motion free = run(model, scene, nullptr, s_states);
    const Motion controlled = run(model, scene, &K, s_states);

    // 4. Files and verdict.
    write_csv(dir / "steer_control.csv", free, controlled);
    plot(dir);
    const double free_lean = largest_lean(free), controlled_lean = largest_lean(controlled);
    std::cout << "free: largest |lean| " << free_lean << " rad"
              << (free.stopped ? " (stopped at t = " + std::to_string(free.t.empty() ? 0.0 : free.t.back()) + ": " +
                                     free.why + ")"
                               : "")
              << "\ncontrolled: largest |lean| " << controlled_lean << " rad over " << kDuration << " s"
              << (controlled.stopped ? " (stopped: " + controlled.why + ")" : "") << "\n"
              << "wrote " << (dir / "steer_control.csv").string() << "\n";
    bool ok = true;
    if (controlled.stopped || controlled.t.empty() || controlled.t.back() < kDuration ||
        controlled_lean > kLean0 * (1 + 1e-9)) {
      std::cout << "FAILED: the controlled bicycle's lean left 0.05 rad\n";
      ok = false;
    }
    if (!(free.stopped || free_lean > 0.5)) {
      std::cout << "FAILED: the free bicycle did not fall (largest lean " << free_lean << " rad)\n";
      ok = false;
    }
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "steer_control: " << e.what() << "\n";
    return 1;
  }
}
