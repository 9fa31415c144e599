// The propagation's stopping rules (core/solver/propagation.h) on two facing squares whose
// links are set by hand: each square gathers F of the other's radiosity, so every
// sweep is B <- E + rho F B_other and the answer is known in closed form. With both
// squares alike, B_k = E (1 + q + ... + q^k) after k sweeps from B_0 = E (q = rho F),
// which converges to E / (1 - q) when q < 1 and grows without bound when q >= 1.
#include "core/solver/propagation.h"
#include "core/hierarchy/hierarchy.h"
#include "tests/solver_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

namespace hrad {
namespace {

// Two unit squares one apart, facing each other, both of reflectance rho and
// exitance e; square 0 gathers f of square 1 and the other way round (V = 1).
struct Pair {
  Scene scene;
  std::unique_ptr<Hierarchy> h;
  std::vector<Element*> els;
  Element* a = nullptr;
  Element* b = nullptr;

  Pair(double rho, double e, float f) {
    SceneBuilder sb("pair", "test");
    const auto m = sb.add_material(test::material(0.5, e), {"t", 0});
    sb.add_polygon(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, m, {"t", 1});
    sb.add_polygon(std::vector<Vec3>{{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}, m, {"t", 2});
    scene = sb.finish("t");
    h = std::make_unique<Hierarchy>(scene, 1);
    els = h->elements();
    for (Element* x : els)
      if (!x->is_cluster()) (x->face == 0 ? a : b) = x;
    // Set here rather than in the material, which must be a physical reflectance in
    // [0, 1]: the divergent case needs rho F above 1.
    for (Element* x : els) x->rho = Rgb::Constant(rho);
    const Link to_a{b, f, 1.0f}, to_b{a, f, 1.0f};
    h->store_links(*a, {&to_a, 1}, 0);
    h->store_links(*b, {&to_b, 1}, 0);
  }
};

// B_k = E (1 - q^(k+1)) / (1 - q): the radiosity after k sweeps from B_0 = E.
double after_sweeps(double e, double q, int k) { return e * (1 - std::pow(q, k + 1)) / (1 - q); }

// rho 0.5, F 0.5 (q = 0.25), E 1: B = 1 / (1 - 0.25) = 4/3 at both squares and at the
// cluster above them (the mean of its children). The stopping rule leaves at most
// about `tolerance` (1e-12) of the largest radiosity undone: compared to 1e-10
// relative.
TEST(Propagation, ConvergesToTheClosedForm) {
  Pair p(0.5, 1.0, 0.5f);
  ASSERT_TRUE(p.a && p.b);
  ASSERT_EQ(p.a->B[0], 1.0);  // starts from B = E
  const PropagationResult r = propagate(p.els, 1e-12, 1000, 1);
  EXPECT_TRUE(r.converged);
  EXPECT_FALSE(r.diverged);
  EXPECT_GT(r.sweeps, 1);
  EXPECT_LT(r.sweeps, 1000);
  for (const Element* e : p.els)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e->B[c], 4.0 / 3, 1e-10 * 4 / 3) << e->id;
  // The last change is what the rule saw: a 0.25 contraction with c q / (1 - q) below
  // the tolerance, so the change itself is below 3 x 1e-12.
  EXPECT_LT(r.last_change, 3e-12);
}

// At the cap the loop stops unconverged, and each of its sweeps was a full Jacobi step:
// after 5 sweeps at q = 0.9 the radiosity is the series' 6th partial sum (exact up to
// round-off: compared to 1e-12 relative). on_sweep saw every sweep with its count.
TEST(Propagation, StopsAtTheSweepCapUnconverged) {
  Pair p(0.9, 1.0, 1.0f);
  std::vector<int> seen;
  const PropagationResult r = propagate(p.els, 1e-12, 5, 1, ClusterReceiver::Isotropic, false,
                                        [&](int sweeps, double change) {
                                          seen.push_back(sweeps);
                                          EXPECT_GT(change, 0.0);
                                        });
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.diverged);
  EXPECT_EQ(r.sweeps, 5);
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3, 4, 5}));
  const double expected = after_sweeps(1.0, 0.9, 5);
  EXPECT_NEAR(p.a->B[0], expected, 1e-12 * expected);
  EXPECT_NEAR(p.b->B[0], expected, 1e-12 * expected);
  // The relative change of sweep 5: (B_5 - B_4) / B_5 = 0.9^5 / B_5 (1e-12 relative).
  EXPECT_NEAR(r.last_change, std::pow(0.9, 5) / expected, 1e-12);
}

// rho F of 1 or more (q = 1.25, and q = 1: no finite solution either): the change
// B_k - B_(k-1) = q^k grows (or stays) every sweep, while the change relative to the
// radiosity falls towards (q - 1) / q. The loop counts the sweeps whose change did not
// fall, from the second on, and reports divergence at the 51st: sweep 52, long before
// the cap and with B still finite. Before, the relative change was counted, which never
// rises: q = 1 ran to the cap, and q = 1.25 ran until B overflowed and its change of
// inf - inf stopped the loop as "converged".
TEST(Propagation, ReportsDivergenceAndStops) {
  for (const double rho : {1.25, 1.0}) {
    SCOPED_TRACE(rho);
    Pair p(rho, 1.0, 1.0f);
    const PropagationResult r = propagate(p.els, 1e-6, 10000, 1);
    EXPECT_TRUE(r.diverged);
    EXPECT_FALSE(r.converged);
    EXPECT_EQ(r.sweeps, 52);
    EXPECT_TRUE(std::isfinite(p.a->B[0]));
  }
}

// A radiosity past the largest double stops the loop at once, as diverged.
TEST(Propagation, OverflowIsDivergence) {
  Pair p(1e200, 1.0, 1.0f);  // B_1 = 1e200, B_2 = inf
  const PropagationResult r = propagate(p.els, 1e-6, 10000, 1);
  EXPECT_TRUE(r.diverged);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.sweeps, 2);
  EXPECT_FALSE(std::isfinite(p.a->B[0]));
}

// No emitter and nothing to gather: the first sweep changes nothing, and a change of
// 0 converges at once.
TEST(Propagation, ZeroChangeConvergesAfterOneSweep) {
  Pair p(0.5, 0.0, 0.5f);
  const PropagationResult r = propagate(p.els, 1e-6, 100, 1);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.sweeps, 1);
  EXPECT_EQ(r.last_change, 0.0);
  EXPECT_EQ(p.a->B[0], 0.0);
}

// n unit squares, square i gathering f of square i + 1 (mod n) with V = 1, all of
// reflectance rho and exitance e: the sweep is B <- E + q P B, P the cyclic shift,
// q = rho f, whose eigenvalues are q times the n-th roots of unity: +-q for n = 2
// (real, as reciprocity makes them), +-q and +-qi for n = 4. Every
// square converges to E / (1 - q).
struct Ring {
  Scene scene;
  std::unique_ptr<Hierarchy> h;
  std::vector<Element*> els;
  std::vector<Element*> squares;
  std::vector<Link> links;

  Ring(int n, double rho, double e, float f) {
    SceneBuilder sb("ring", "test");
    const auto m = sb.add_material(test::material(0.5, e), {"t", 0});
    for (int i = 0; i < n; ++i) {
      const double x = 2.0 * i;
      sb.add_polygon(std::vector<Vec3>{{x, 0, 0}, {x + 1, 0, 0}, {x + 1, 1, 0}, {x, 1, 0}}, m,
                     {"t", i + 1});
    }
    scene = sb.finish("t");
    h = std::make_unique<Hierarchy>(scene, 1);
    els = h->elements();
    squares.resize(static_cast<std::size_t>(n));
    for (Element* x : els)
      if (!x->is_cluster()) squares[x->face] = x;
    for (Element* x : els) x->rho = Rgb::Constant(rho);
    for (int i = 0; i < n; ++i)
      links.push_back(Link{squares[static_cast<std::size_t>((i + 1) % n)], f, 1.0f});
    for (int i = 0; i < n; ++i)
      h->store_links(*squares[static_cast<std::size_t>(i)],
                     {&links[static_cast<std::size_t>(i)], 1}, 0);
  }
};

// Accelerated, the pair with q = 0.9 (eigenvalues +-0.9, the hardest real case: the
// negative one alternates) reaches the closed form 10 to the tolerance in far fewer
// sweeps than plain Jacobi (which needs about 270 for 1e-12: 0.9^k). The contraction it
// measured is q, and handed to a second propagation it accelerates from the start.
TEST(Propagation, ChebyshevAccelerationOnARealSpectrum) {
  Pair plain(0.9, 1.0, 1.0f);
  const PropagationResult p = propagate(plain.els, 1e-12, 10000, 1, ClusterReceiver::Isotropic,
                                        false, {}, /*contraction=*/-1);
  EXPECT_TRUE(p.converged);
  EXPECT_EQ(p.contraction, 0.0);
  EXPECT_GT(p.sweeps, 250);

  Pair fast(0.9, 1.0, 1.0f);
  const PropagationResult r = propagate(fast.els, 1e-12, 10000, 1);
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(r.accelerated);
  EXPECT_NEAR(r.contraction, 0.9, 1e-9);
  EXPECT_LT(r.sweeps, 90);  // 4 plain sweeps, then about 0.63 per sweep
  for (const Element* e : fast.els) EXPECT_NEAR(e->B[0], 10.0, 1e-10) << e->id;

  Pair hinted(0.9, 1.0, 1.0f);
  const PropagationResult h =
      propagate(hinted.els, 1e-12, 10000, 1, ClusterReceiver::Isotropic, false, {}, r.contraction);
  EXPECT_TRUE(h.converged);
  EXPECT_LT(h.sweeps, r.sweeps);
  for (const Element* e : hinted.els) EXPECT_NEAR(e->B[0], 10.0, 1e-10) << e->id;
}

// Near 1 (q = 0.999, a closed furnace of that reflectance) the first accelerated
// sweeps' changes rise about ninefold before they fall: the acceleration keeps going
// (it gave up at eight times the smallest change, and plain sweeps, 0.999^k, needed
// thousands) and reaches the closed form 1000 in a few hundred sweeps.
TEST(Propagation, ChebyshevAccelerationNearOne) {
  Pair p(0.999, 1.0, 1.0f);
  const PropagationResult r = propagate(p.els, 1e-10, 100000, 1);
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(r.accelerated);
  EXPECT_NEAR(r.contraction, 0.999, 1e-6);
  EXPECT_LT(r.sweeps, 600);
  for (const Element* e : p.els) EXPECT_NEAR(e->B[0], 1000.0, 1e-4) << e->id;
}

// Told a contraction below the truth (0.5 for 0.9), the acceleration sees its sweeps
// fall too slowly, finds the interval again and still converges to the closed form.
TEST(Propagation, ChebyshevFindsAnUnderestimatedContraction) {
  Pair p(0.9, 1.0, 1.0f);
  const PropagationResult r =
      propagate(p.els, 1e-12, 10000, 1, ClusterReceiver::Isotropic, false, {}, 0.5);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.contraction, 0.85);
  EXPECT_LT(r.sweeps, 120);
  for (const Element* e : p.els) EXPECT_NEAR(e->B[0], 10.0, 1e-10) << e->id;
}

// Four squares in a ring, only square 0 emitting: the sweep's eigenvalues are +-0.9
// and +-0.9i, and the emitter excites them all. The imaginary pair lies far outside
// the ellipse Chebyshev over [-0.9, 0.9] converges in: the accelerated changes grow,
// the propagation gives the acceleration up, and plain sweeps converge to the closed
// form B_0 = 1 / (1 - q^4), B_i = q^(4 - i) B_0.
TEST(Propagation, ComplexSpectrumFallsBackToPlainSweeps) {
  Ring ring(4, 0.9, 1.0, 1.0f);
  for (std::size_t i = 1; i < 4; ++i) {
    ring.squares[i]->emission = Rgb::Zero();
    ring.squares[i]->B = Rgb::Zero();
  }
  const PropagationResult r =
      propagate(ring.els, 1e-12, 10000, 1, ClusterReceiver::Isotropic, false, {}, 0.9);
  EXPECT_TRUE(r.converged);
  EXPECT_FALSE(r.accelerated);
  EXPECT_EQ(r.contraction, 0.0);
  const double b0 = 1 / (1 - std::pow(0.9, 4));
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(ring.squares[i]->B[0], std::pow(0.9, (4 - static_cast<int>(i)) % 4) * b0, 1e-9)
        << i;
}

}  // namespace
}  // namespace hrad
