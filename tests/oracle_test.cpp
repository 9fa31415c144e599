// The oracles' link error: the occlusion weight of links with a cluster end
// (oracles/oracle.h) and the directional cluster model's sums (add_by_axis in
// core/element.h) that those links' form factors come from.
#include "core/element.h"
#include "oracles/oracle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hrad {
namespace {

// Elements hold an atomic and are neither copied nor moved: set one in place.
void set(Element& e, ElementKind kind, double area, double rho, double b) {
  e.kind = kind;
  e.area = area;
  e.rho = Rgb::Constant(rho);
  e.B = Rgb::Constant(b);
}

// A link carrying power P = rho_r B_s A_r F just under the threshold is accepted
// between surfaces whatever its visibility, and between a surface and a cluster
// only while every visibility ray was unblocked (V = 1); with V < 1 (partial or
// none) the cluster link must carry kOccludedClusterWeight times less.
TEST(Oracle, OccludedClusterLinksAreWeighed) {
  Element rs, ss, rc, sc;
  set(rs, ElementKind::Surface, 2.0, 0.5, 0);
  set(ss, ElementKind::Surface, 1.0, 0.5, 3.0);
  set(rc, ElementKind::Cluster, 2.0, 0.5, 0);
  set(sc, ElementKind::Cluster, 1.0, 0.5, 3.0);
  const double power_per_f = 0.5 * 3.0 * 2.0;
  const double f = 0.1;
  const OracleThresholds t{1.01 * power_per_f * f};  // P is just under eps_power
  for (const char* name : {"bf", "error"}) {
    SCOPED_TRACE(name);
    const auto oracle = make_oracle(name);
    for (const double v : {1.0, 0.5, 0.0}) {
      const LinkEstimate surf{&rs, &ss, f, v, 0};
      EXPECT_EQ(oracle->judge(surf, t).decision, Decision::Accept) << "V " << v;
      for (const auto& [r, s] : {std::pair{&rc, &ss}, std::pair{&rs, &sc}, std::pair{&rc, &sc}}) {
        const LinkEstimate l{r, s, f, v, 0};
        const Verdict verdict = oracle->judge(l, t);
        EXPECT_EQ(verdict.decision, v < 1 ? Decision::Refine : Decision::Accept) << "V " << v;
        EXPECT_NEAR(verdict.error, power_per_f * f * (v < 1 ? kOccludedClusterWeight : 1.0), 1e-12);
        // ... and is accepted once its weighted error is under the threshold.
        const OracleThresholds loose{1.01 * kOccludedClusterWeight * power_per_f * f};
        EXPECT_EQ(oracle->judge(l, loose).decision, Decision::Accept) << "V " << v;
      }
    }
  }
}

// A receiver darker than the scene's mean is judged against a threshold scaled by its
// irradiance over the mean, never below kDarkThresholdFloor of eps and never above
// eps; one that has gathered nothing yet (B = E), or with no mean given, keeps eps.
// Exact arithmetic: tolerance 1e-12 relative.
TEST(Oracle, DarkReceiversAreJudgedAgainstTheirOwnLight) {
  Element r, s;
  set(r, ElementKind::Surface, 1.0, 0.5, 0);
  set(s, ElementKind::Surface, 1.0, 0.5, 3.0);
  const LinkEstimate l{&r, &s, 0.1, 1, 0};
  const OracleThresholds t{2.0, 4.0};  // mean irradiance 4
  const auto threshold_at = [&](double b) {
    r.B = Rgb::Constant(b);
    return receiver_threshold(l, t);
  };
  EXPECT_DOUBLE_EQ(threshold_at(0), 2.0);          // nothing gathered yet
  EXPECT_NEAR(threshold_at(1.0), 2.0 * 0.5, 1e-12);  // E_r = 1 / 0.5 = 2: half the mean
  EXPECT_NEAR(threshold_at(0.1), 2.0 * kDarkThresholdFloor, 1e-12);  // E_r 0.2: the floor
  EXPECT_DOUBLE_EQ(threshold_at(5.0), 2.0);        // brighter than the mean: eps itself
  // Emission is not light gathered: an emitter of exitance 1 with B = 1.5 has E_r = 1.
  r.emission = Rgb::Constant(1.0);
  EXPECT_NEAR(threshold_at(1.5), 2.0 * 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(threshold_at(1.0), 2.0);  // B = E: nothing gathered
  r.emission = Rgb::Zero();
  // The largest channel's irradiance decides: a red-lit receiver is as bright as its red.
  r.B = Rgb(2.0, 0.1, 0.1);
  EXPECT_DOUBLE_EQ(receiver_threshold(l, t), 2.0);
  // No mean: thresholds are not scaled.
  r.B = Rgb::Constant(0.1);
  EXPECT_DOUBLE_EQ(receiver_threshold(l, OracleThresholds{2.0}), 2.0);
  // Both oracles use it: a link of error 0.75 (rho 0.5 x B_s 3 x A 1 x 0.5, the F of
  // `bf` and the F spread of `error`) passes eps 1 for a bright receiver and fails it
  // for a dark one (threshold 0.25).
  const LinkEstimate big{&r, &s, 0.5, 1, 0.5};
  for (const char* name : {"bf", "error"}) {
    SCOPED_TRACE(name);
    const auto oracle = make_oracle(name);
    const OracleThresholds one{1.0, 4.0};
    r.B = Rgb::Constant(5.0);
    EXPECT_NEAR(oracle->judge(big, one).error, 0.75, 1e-12);
    EXPECT_EQ(oracle->judge(big, one).decision, Decision::Accept);
    r.B = Rgb::Constant(0.1);
    EXPECT_EQ(oracle->judge(big, one).decision, Decision::Refine);
  }
}

// Fibonacci-sphere mean of a cluster's projected area over all directions.
double mean_projected_area(const Element& c) {
  const int n = 20000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n;
    const double r = std::sqrt(1 - z * z);
    const double phi = i * std::numbers::pi * (3 - std::sqrt(5.0));
    sum += c.projected_area(Vec3(r * std::cos(phi), r * std::sin(phi), z));
  }
  return sum / n;
}

// The directional model is exact for axis-aligned members and, for tilted ones,
// right on average: over all directions a member's mean projected area is A/4. With
// the old weights max(0, +-n_i) a member facing (1,1,1)/sqrt 3 came out at
// sqrt(3)/4 A on average (73 % high) and 3/sqrt 3 = 1.73 A seen along its own normal.
TEST(DirectionalClusterModel, AxisAlignedExactTiltedRightOnAverage) {
  Element c;
  c.kind = ElementKind::Cluster;
  add_by_axis(c.dir_area, Vec3(0, 1, 0), 2.0f);   // floor-like, area 2
  add_by_axis(c.dir_area, Vec3(-1, 0, 0), 1.0f);  // wall-like, area 1
  EXPECT_NEAR(c.projected_area(Vec3(0, 1, 0)), 2.0, 1e-6);
  EXPECT_NEAR(c.projected_area(Vec3(-1, 0, 0)), 1.0, 1e-6);
  const Vec3 d = Vec3(-1, 1, 0).normalized();  // exact: 2 cos 45 + 1 cos 45
  EXPECT_NEAR(c.projected_area(d), 3 * std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(c.projected_area(Vec3(0, -1, 0)), 0.0, 1e-12);
  EXPECT_NEAR(mean_projected_area(c), 3.0 / 4, 1e-3);

  for (const Vec3& n : {Vec3(1, 1, 1), Vec3(1, -2, 0.5), Vec3(0, 0.3, -1)}) {
    Element t;
    t.kind = ElementKind::Cluster;
    add_by_axis(t.dir_area, Vec3(n.normalized()), 1.0f);
    EXPECT_NEAR(mean_projected_area(t), 0.25, 1e-3) << n.transpose();
    // Never more than the member's whole area, in any direction.
    EXPECT_LE(t.projected_area(n.normalized()), 1.0 + 1e-6);
  }
}

}  // namespace
}  // namespace hrad
