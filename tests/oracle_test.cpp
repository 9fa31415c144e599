// The oracles' link error: the occlusion weight of links with a cluster end
// (oracles/oracle.h) and the directional cluster model's sums (add_by_axis in
// core/hierarchy/element.h) that those links' form factors come from.
#include "oracles/oracle.h"
#include "core/hierarchy/element.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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
  EXPECT_DOUBLE_EQ(threshold_at(0), 2.0);            // nothing gathered yet
  EXPECT_NEAR(threshold_at(1.0), 2.0 * 0.5, 1e-12);  // E_r = 1 / 0.5 = 2: half the mean
  EXPECT_NEAR(threshold_at(0.1), 2.0 * kDarkThresholdFloor, 1e-12);  // E_r 0.2: the floor
  EXPECT_DOUBLE_EQ(threshold_at(5.0), 2.0);  // brighter than the mean: eps itself
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

// Where the dark-receiver scaling's branches meet: the clamp's ends are reached
// exactly (E_r = the mean: factor 1; E_r = kDarkThresholdFloor x the mean: the floor);
// a channel the receiver does not reflect (rho 0) says nothing about its light however
// bright it is; light lost since the last solution (B below E) counts as gathered, at
// irradiance 0, so the floor; and a mean that is not positive (0, negative, NaN) turns
// the scaling off. Exact arithmetic on dyadic values: tolerance 0 (EXPECT_EQ).
TEST(Oracle, DarkScalingEdgeCases) {
  Element r, s;
  set(r, ElementKind::Surface, 1.0, 0.5, 0);
  set(s, ElementKind::Surface, 1.0, 0.5, 3.0);
  const LinkEstimate l{&r, &s, 0.1, 1, 0};
  const OracleThresholds t{2.0, 4.0};
  r.B = Rgb::Constant(2.0);  // E_r = 4: the mean itself
  EXPECT_EQ(receiver_threshold(l, t), 2.0);
  r.B = Rgb::Constant(0.5);  // E_r = 1: a quarter of the mean, the floor exactly
  EXPECT_EQ(receiver_threshold(l, t), 2.0 * kDarkThresholdFloor);
  r.B = Rgb::Constant(0.75);  // E_r = 1.5: 3/8 of the mean, inside the clamp
  EXPECT_EQ(receiver_threshold(l, t), 2.0 * 0.375);
  // Green is bright (B 3) but not reflected: red and blue's E_r 0.2 decide, the floor.
  r.rho = Rgb(0.5, 0.0, 0.5);
  r.B = Rgb(0.1, 3.0, 0.1);
  EXPECT_EQ(receiver_threshold(l, t), 2.0 * kDarkThresholdFloor);
  // Only the unreflected channel changed: gathered, but at no known irradiance.
  r.B = Rgb(0.0, 3.0, 0.0);
  EXPECT_EQ(receiver_threshold(l, t), 2.0 * kDarkThresholdFloor);
  r.rho = Rgb::Constant(0.5);
  // An emitter whose B fell below its E has gathered (lost) light: irradiance 0.
  r.emission = Rgb::Constant(1.0);
  r.B = Rgb::Constant(0.5);
  EXPECT_EQ(receiver_threshold(l, t), 2.0 * kDarkThresholdFloor);
  r.emission = Rgb::Zero();
  r.B = Rgb::Constant(0.1);
  for (const double mean : {0.0, -4.0, std::nan("")})
    EXPECT_EQ(receiver_threshold(l, OracleThresholds{2.0, mean}), 2.0) << mean;
}

// `bf`: error = max over channels of rho_r B_s, times A_r and the unoccluded F: here
// rho_r (0.5, 0.25, 1) x B_s (2, 8, 1) = (1, 2, 1), so 2 (not max rho x max B = 8),
// times A_r 2 (the source's area does not count) times F 0.125 = 0.5. Between surfaces
// neither the visibility (F is unoccluded, so shadow boundaries are still refined) nor
// the F spread changes it. Accepted iff the error is below the threshold, strictly. All
// values dyadic: exact, tolerance 0 (EXPECT_EQ).
TEST(Oracle, BfErrorIsTheReflectedPowerOfTheUnoccludedFormFactor) {
  Element r, s;
  set(r, ElementKind::Surface, 2.0, 0, 0);
  set(s, ElementKind::Surface, 64.0, 0, 0);
  r.rho = Rgb(0.5, 0.25, 1.0);
  s.B = Rgb(2.0, 8.0, 1.0);
  EXPECT_EQ(reflected_power_scale(r, s), 4.0);
  const auto bf = make_oracle("bf");
  for (const double v : {1.0, 0.5, 0.0})
    for (const double spread : {0.0, 0.1}) {
      const LinkEstimate l{&r, &s, 0.125, v, spread};
      EXPECT_EQ(occlusion_weight(l), 1.0);
      EXPECT_EQ(bf->judge(l, OracleThresholds{1.0}).error, 0.5) << "V " << v;
    }
  const LinkEstimate l{&r, &s, 0.125, 1, 0};
  EXPECT_EQ(bf->judge(l, OracleThresholds{0.5}).decision, Decision::Refine);  // not below
  EXPECT_EQ(bf->judge(l, OracleThresholds{std::nextafter(0.5, 1.0)}).decision, Decision::Accept);
  // A cluster end with V < 1 weighs kOccludedClusterWeight (8): 4 against 4 + 1 ulp.
  Element c;
  set(c, ElementKind::Cluster, 2.0, 0, 0);
  c.rho = r.rho;
  const LinkEstimate occluded{&c, &s, 0.125, 0.5, 0};
  EXPECT_EQ(occlusion_weight(occluded), kOccludedClusterWeight);
  EXPECT_EQ(bf->judge(occluded, OracleThresholds{1.0}).error, 4.0);
  EXPECT_EQ(bf->judge(occluded, OracleThresholds{4.0}).decision, Decision::Refine);
  EXPECT_EQ(bf->judge(occluded, OracleThresholds{std::nextafter(4.0, 5.0)}).decision,
            Decision::Accept);
  // Nothing reflected (a black receiver, or a dark source): error 0, always accepted.
  r.rho = Rgb::Zero();
  EXPECT_EQ(bf->judge(l, OracleThresholds{1e-300}).error, 0.0);
  EXPECT_EQ(bf->judge(l, OracleThresholds{1e-300}).decision, Decision::Accept);
}

// `error`: error = rho_r B_s A_r (4 here) x uncertainty. Between surfaces the
// uncertainty is the F spread (0.0625), plus F (0.125) only while the visibility is
// partial (0 < V < 1): fully visible and fully hidden pairs carry no shadow boundary.
// With a cluster end it is F whatever the spread (clusters have none), weighted by
// kOccludedClusterWeight when V < 1, V = 0 included. Dyadic values: exact, tolerance 0.
TEST(Oracle, ErrorOracleWeighsSpreadAndPartialVisibility) {
  Element rs, ss, rc, sc;
  set(rs, ElementKind::Surface, 2.0, 0.5, 0);
  set(ss, ElementKind::Surface, 1.0, 0.5, 4.0);
  set(rc, ElementKind::Cluster, 2.0, 0.5, 0);
  set(sc, ElementKind::Cluster, 1.0, 0.5, 4.0);
  const auto oracle = make_oracle("error");
  const OracleThresholds t{1.0};
  const double f = 0.125, spread = 0.0625;
  const auto err = [&](const Element& r, const Element& s, double v) {
    return oracle->judge(LinkEstimate{&r, &s, f, v, spread}, t).error;
  };
  EXPECT_EQ(err(rs, ss, 1.0), 4 * spread);            // 0.25
  EXPECT_EQ(err(rs, ss, 0.0), 4 * spread);            // hidden: no boundary either
  EXPECT_EQ(err(rs, ss, 0.5), 4 * (spread + f));      // 0.75
  EXPECT_EQ(err(rs, ss, 0.96875), 4 * (spread + f));  // just below 1 is partial
  EXPECT_EQ(err(rs, ss, 0.03125), 4 * (spread + f));  // just above 0 too
  for (const auto& [r, s] : {std::pair{&rc, &ss}, std::pair{&rs, &sc}, std::pair{&rc, &sc}}) {
    EXPECT_EQ(err(*r, *s, 1.0), 4 * f);  // 0.5: the spread is not used
    EXPECT_EQ(err(*r, *s, 0.5), 4 * f * kOccludedClusterWeight);
    EXPECT_EQ(err(*r, *s, 0.0), 4 * f * kOccludedClusterWeight);
  }
  // Strictly below the threshold: a surface pair fully visible at error 0.25.
  const LinkEstimate l{&rs, &ss, f, 1, spread};
  EXPECT_EQ(oracle->judge(l, OracleThresholds{0.25}).decision, Decision::Refine);
  EXPECT_EQ(oracle->judge(l, OracleThresholds{std::nextafter(0.25, 1.0)}).decision,
            Decision::Accept);
  // A fully visible surface pair with no spread has nothing uncertain: error 0.
  EXPECT_EQ(oracle->judge(LinkEstimate{&rs, &ss, f, 1, 0}, t).error, 0.0);
}

// The shadow test (kShadowContrast): a partly visible surface pair is refined while
// the radiosity it would bring at full visibility, rho_r B_s F, times 2 min(V, 1 - V)
// exceeds the contrast times the receiver's reflected radiosity B_r - E_r. Here
// rho_r B_s F = 0.5 x 8 x 0.125 = 0.5 and B_r - E_r = 1.25 - 0.25 = 1, so at V = 1/4 the
// shadow is 0.5 x 0.5 = 0.25 of the receiver's light: refined at a contrast just
// under 0.25, not at 0.25 (strictly above). Dyadic values: exact, tolerance 0.
TEST(Oracle, SharpShadowsAcrossSurfaceReceiversAreRefined) {
  Element r, s, c;
  set(r, ElementKind::Surface, 2.0, 0.5, 1.25);
  r.emission = Rgb::Constant(0.25);
  set(s, ElementKind::Surface, 1.0, 0.5, 8.0);
  set(c, ElementKind::Cluster, 1.0, 0.5, 8.0);
  const double f = 0.125;
  const double just_under = std::nextafter(0.25, 0.0);
  for (const double v : {0.25, 0.75}) {  // 2 min(V, 1 - V) = 1/2 either way
    const LinkEstimate l{&r, &s, f, v, 0};
    EXPECT_TRUE(shadow_too_sharp(l, just_under)) << "V " << v;
    EXPECT_FALSE(shadow_too_sharp(l, 0.25)) << "V " << v;
  }
  EXPECT_TRUE(shadow_too_sharp(LinkEstimate{&r, &s, f, 0.5, 0}, just_under * 2));
  // Wholly open or hidden pairs, cluster ends, a contrast of 0 and a receiver that has
  // gathered nothing yet (B = E) are never refined by it.
  for (const double v : {0.0, 1.0}) EXPECT_FALSE(shadow_too_sharp(LinkEstimate{&r, &s, f, v, 0}));
  EXPECT_FALSE(shadow_too_sharp(LinkEstimate{&r, &c, f, 0.5, 0}));
  EXPECT_FALSE(shadow_too_sharp(LinkEstimate{&c, &s, f, 0.5, 0}));
  EXPECT_FALSE(shadow_too_sharp(LinkEstimate{&r, &s, f, 0.5, 0}, 0.0));
  Element dark;
  set(dark, ElementKind::Surface, 2.0, 0.5, 0.25);
  dark.emission = Rgb::Constant(0.25);
  EXPECT_FALSE(shadow_too_sharp(LinkEstimate{&dark, &s, f, 0.5, 0}));
  // Both oracles refine such a link whatever its power (error rho_r B_s A_r F = 0.5 x 8
  // x 2 x 0.125 = 1 in both, under a threshold of 4), and accept it with the test off.
  for (const char* name : {"bf", "error"}) {
    SCOPED_TRACE(name);
    const LinkEstimate l{&r, &s, f, 0.5, 0};
    const Verdict v = make_oracle(name)->judge(l, OracleThresholds{4.0});
    EXPECT_EQ(v.decision, Decision::Refine);
    EXPECT_EQ(v.error, 1.0);
    EXPECT_EQ(
        make_oracle(name, {{"shadow_contrast", "0"}})->judge(l, OracleThresholds{4.0}).decision,
        Decision::Accept);
  }
}

// The registry: each oracle by its name, with its own name and spread needs; the names
// listed in order; an unknown name is an error that lists the known ones.
TEST(Oracle, RegistryMakesEachOracleByName) {
  EXPECT_EQ(oracle_names(), (std::vector<std::string>{"bf", "error"}));
  const auto bf = make_oracle("bf");
  const auto error = make_oracle("error");
  ASSERT_TRUE(bf && error);
  EXPECT_STREQ(bf->name(), "bf");
  EXPECT_STREQ(error->name(), "error");
  EXPECT_FALSE(bf->needs_spread());
  EXPECT_TRUE(error->needs_spread());
  EXPECT_NE(make_oracle("bf").get(), bf.get());  // a new instance per call
  try {
    (void)make_oracle("BF");  // names are case-sensitive
    ADD_FAILURE() << "no exception for an unknown oracle";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown oracle 'BF' (known: bf, error)");
  }
  EXPECT_THROW((void)make_oracle(""), std::invalid_argument);
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

// Coloured light: each channel is weighted by the strongest channel's emitted power over
// its own, at most kMaxChannelWeight; grey light (or none) weighs every channel 1.
TEST(Oracle, ChannelWeightsJudgeEachChannelAgainstItsOwnLight) {
  EXPECT_TRUE((channel_weights(Rgb(3, 3, 3)) == Rgb::Ones()).all());
  EXPECT_TRUE((channel_weights(Rgb::Zero()) == Rgb::Ones()).all());
  EXPECT_TRUE((channel_weights(Rgb(8, 2, 1)) == Rgb(1, 4, 8)).all());
  EXPECT_TRUE((channel_weights(Rgb(1, 4, 2)) == Rgb(4, 1, 2)).all());
  // A channel under a hundredth of the strongest (or without light) weighs 100.
  EXPECT_TRUE(
      (channel_weights(Rgb(1, 0, 1e-9)) == Rgb(1, kMaxChannelWeight, kMaxChannelWeight)).all());
  EXPECT_TRUE((channel_weights(Rgb(1, 1, 1e300 * 1e300)) == Rgb::Ones()).all());  // inf: unweighted

  // A blue receiver lit by a source whose blue is an eighth of its red: unweighted, red
  // decides (rho B = (0.125, 0.125, 0.125 x 0.75)); with the weights of a light of that
  // colour (1, 1, 8), blue does: 0.75, six times more, and the link is refined.
  Element r, s;
  set(r, ElementKind::Surface, 1.0, 0, 0);
  set(s, ElementKind::Surface, 1.0, 0, 0);
  r.rho = Rgb(0.125, 0.125, 0.75);
  s.B = Rgb(1, 1, 0.125);
  const Rgb w = channel_weights(Rgb(8, 8, 1));
  EXPECT_EQ(reflected_power_scale(r, s), 0.125);
  EXPECT_EQ(reflected_power_scale(r, s, w), 0.75);
  const auto bf = make_oracle("bf");
  const LinkEstimate l{&r, &s, 0.5, 1, 0};
  EXPECT_EQ(bf->judge(l, OracleThresholds{0.25}).decision, Decision::Accept);
  EXPECT_EQ(bf->judge(l, OracleThresholds{0.25, 0, w}).decision, Decision::Refine);
  EXPECT_EQ(bf->judge(l, OracleThresholds{0.25, 0, w}).error, 0.375);
  // The dark receiver's irradiance is weighed alike: blue (B - E) / rho = 0.5 x 8 = 4
  // against a mean of 8 (threshold x 1/2), where red alone gives 1/8 (x kDarkThresholdFloor).
  r.B = Rgb(0.125 * 0.125, 0.125 * 0.125, 0.75 * 0.5);
  EXPECT_EQ(receiver_threshold(l, OracleThresholds{1.0, 8.0}), kDarkThresholdFloor);
  EXPECT_EQ(receiver_threshold(l, OracleThresholds{1.0, 8.0, w}), 0.5);
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
