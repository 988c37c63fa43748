#include "core/character/demo_character.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <numbers>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <tbb/parallel_for.h>

namespace cagewrap {
namespace {

using glm::dvec3;

struct JointSpec {
  std::string name;
  int parent;
  dvec3 head;       // joint position (world, rest)
  dvec3 tail;       // end of its bone
  bool arm_frame;   // bending axis from (bone x forward) rather than world X
  double r_head = 0, r_tail = 0;  // capsule radii of the fingers and the tail (0 for the others)
};

// What the variant changes.
struct Shape {
  bool arms_down = false;  // arms hanging, hands at the thighs, legs together
  bool extras = false;     // fingers and a tail
  bool quadruped = false;  // four legs under a level body, a tail
  bool grouped() const { return arms_down || extras || quadruped; }
};

Shape shape_of(DemoVariant v) {
  return {v == DemoVariant::kArmsDown || v == DemoVariant::kArmsDownTail,
          v == DemoVariant::kTail || v == DemoVariant::kArmsDownTail, v == DemoVariant::kQuadruped};
}

constexpr int kTailBones = 12;
constexpr int kQuadrupedTailBones = 8;

// "tail_01" for i = 0.
std::string tail_bone_name(int i) { return (i < 9 ? "tail_0" : "tail_") + std::to_string(i + 1); }

// 0 -> 1 -> 0 over a clip of length T (a raised cosine).
double rise_and_return(double t, double T) { return 0.5 - 0.5 * std::cos(2 * std::numbers::pi * t / T); }
struct FingerLayout {
  const char* name;
  double across;       // offset across the palm, in finger spacings (+ toward the thumb)
  double along;        // offset of the knuckle along the hand, metres
  double spread;       // sideways tilt of the finger (+ toward the thumb)
  double length[3];    // phalanges, metres
  double r0, r1;       // radius at the knuckle and at the tip
};
// The radii stay above sqrt(3) / 2 of the default cell (0.011 m), so that every fingertip holds a
// grid point and none breaks off; the fingers fan out by 12.5 degrees from one to the next, so
// that the gaps between them (which a cell can resolve only from about a cell wide) open quickly.
constexpr FingerLayout kFingers[] = {
    {"index", 1.5, 0.0, 0.33, {0.040, 0.025, 0.020}, 0.011, 0.0097},
    {"middle", 0.5, 0.004, 0.11, {0.045, 0.028, 0.022}, 0.011, 0.0097},
    {"ring", -0.5, 0.0, -0.11, {0.042, 0.026, 0.021}, 0.011, 0.0097},
    {"little", -1.5, -0.01, -0.33, {0.032, 0.021, 0.018}, 0.0102, 0.0096},
};
constexpr double kFingerSpacing = 0.026;  // centre to centre at the knuckles: 4 mm apart, 1.3 cm at the first joint
constexpr double kKnuckle = 0.088;        // knuckles from the wrist, along the hand

// The hand's axes: u along it, w across the palm toward the thumb, the palm facing +Z.
void hand_axes(const JointSpec& hand, double side, dvec3& u, dvec3& w) {
  u = glm::normalize(hand.tail - hand.head);
  w = side * glm::normalize(glm::cross(dvec3(0, 0, 1), u));
}

// Fingers: three phalanges each, straight at rest, children of the hand (j.back()).
void add_fingers(std::vector<JointSpec>& j, double side) {
  const std::string sfx = side > 0 ? ".L" : ".R";
  const int hand = static_cast<int>(j.size()) - 1;
  dvec3 u, w;
  hand_axes(j[hand], side, u, w);
  const dvec3 wrist = j[hand].head;
  auto add_finger = [&](const std::string& name, dvec3 base, dvec3 dir, const double* len, double r0, double r1) {
    const double total = len[0] + len[1] + len[2];
    double at = 0;
    int parent = hand;
    for (int k = 0; k < 3; ++k) {
      dvec3 head = base + at * dir, tail = base + (at + len[k]) * dir;
      double ra = r0 + (r1 - r0) * at / total, rb = r0 + (r1 - r0) * (at + len[k]) / total;
      j.push_back({"finger_" + name + "_" + std::to_string(k + 1) + sfx, parent, head, tail, true, ra, rb});
      parent = static_cast<int>(j.size()) - 1;
      at += len[k];
    }
  };
  // The thumb leaves the side of the palm, out toward the thumb side and forward.
  const double thumb_len[3] = {0.042, 0.032, 0.026};
  add_finger("thumb", wrist + 0.02 * u + 0.026 * w, glm::normalize(0.5 * u + 0.8 * w + 0.4 * dvec3(0, 0, 1)), thumb_len,
             0.013, 0.0105);
  for (const FingerLayout& f : kFingers)
    add_finger(f.name, wrist + (kKnuckle + f.along) * u + f.across * kFingerSpacing * w, glm::normalize(u + f.spread * w),
               f.length, f.r0, f.r1);
}

// The rest skeleton, A-pose: arms 45 degrees below horizontal.
// The quadruped's skeleton: a level spine from the hips (back) to the chest (front), facing +Z, the
// front legs (shoulder blade, upper arm, forearm, paw) children of the chest, the hind legs of the
// hips, the same joint names as the biped's so that the groups and clips find them; legs 0.2 m apart,
// the elbows against the chest and the thighs against the belly.
std::vector<JointSpec> quadruped_specs() {
  std::vector<JointSpec> j;
  j.push_back({"hips", -1, {0, 0.62, -0.30}, {0, 0.63, -0.10}, false});
  j.push_back({"spine", 0, {0, 0.63, -0.10}, {0, 0.645, 0.12}, false});
  j.push_back({"chest", 1, {0, 0.645, 0.12}, {0, 0.65, 0.30}, false});
  j.push_back({"neck", 2, {0, 0.65, 0.30}, {0, 0.79, 0.43}, false});
  j.push_back({"head", 3, {0, 0.79, 0.43}, {0, 0.80, 0.62}, false});
  for (double side : {1.0, -1.0}) {
    const std::string sfx = side > 0 ? ".L" : ".R";
    const int base = static_cast<int>(j.size());
    j.push_back({"shoulder" + sfx, 2, {side * 0.07, 0.66, 0.22}, {side * 0.10, 0.50, 0.27}, false});
    j.push_back({"upper_arm" + sfx, base, {side * 0.10, 0.50, 0.27}, {side * 0.10, 0.30, 0.23}, false});
    j.push_back({"forearm" + sfx, base + 1, {side * 0.10, 0.30, 0.23}, {side * 0.10, 0.07, 0.25}, false});
    j.push_back({"hand" + sfx, base + 2, {side * 0.10, 0.07, 0.25}, {side * 0.10, 0.025, 0.32}, false});
  }
  for (double side : {1.0, -1.0}) {
    const std::string sfx = side > 0 ? ".L" : ".R";
    const int base = static_cast<int>(j.size());
    j.push_back({"thigh" + sfx, 0, {side * 0.09, 0.60, -0.28}, {side * 0.10, 0.37, -0.19}, false});
    j.push_back({"shin" + sfx, base, {side * 0.10, 0.37, -0.19}, {side * 0.10, 0.15, -0.33}, false});
    j.push_back({"foot" + sfx, base + 1, {side * 0.10, 0.15, -0.33}, {side * 0.10, 0.035, -0.29}, false});
    j.push_back({"toes" + sfx, base + 2, {side * 0.10, 0.035, -0.29}, {side * 0.10, 0.025, -0.22}, false});
  }
  // The tail: from the top of the rump, backward and a little up, 0.55 m.
  dvec3 p(0, 0.67, -0.41);
  for (int i = 0; i < kQuadrupedTailBones; ++i) {
    const double angle = (25.0 - 5.0 * i) * std::numbers::pi / 180.0;  // above the horizontal
    dvec3 next = p + 0.07 * dvec3(0, std::sin(angle), -std::cos(angle));
    const std::string name = tail_bone_name(i);
    j.push_back({name, i == 0 ? 0 : static_cast<int>(j.size()) - 1, p, next, false,
                 0.035 - 0.025 * i / kQuadrupedTailBones, 0.035 - 0.025 * (i + 1) / kQuadrupedTailBones});
    p = next;
  }
  return j;
}

std::vector<JointSpec> joint_specs(const Shape& shape) {
  if (shape.quadruped) return quadruped_specs();
  const double s = std::sqrt(0.5);
  auto arm = [&](double side, dvec3 shoulder, double len) { return shoulder + len * dvec3(side * s, -s, 0); };
  std::vector<JointSpec> j;
  j.push_back({"hips", -1, {0, 0.95, 0}, {0, 1.07, 0}, false});
  j.push_back({"spine", 0, {0, 1.07, 0}, {0, 1.25, 0}, false});
  j.push_back({"chest", 1, {0, 1.25, 0}, {0, 1.46, 0}, false});
  j.push_back({"neck", 2, {0, 1.46, 0}, {0, 1.56, 0}, false});
  j.push_back({"head", 3, {0, 1.56, 0}, {0, 1.76, 0}, false});
  for (double side : {1.0, -1.0}) {
    const char* sfx = side > 0 ? ".L" : ".R";
    int chest = 2;
    int base = static_cast<int>(j.size());
    dvec3 clav(side * 0.04, 1.41, 0), sh(side * 0.17, 1.42, 0);
    dvec3 elbow, wrist, hand_end;
    if (!shape.arms_down) {
      elbow = arm(side, sh, 0.28), wrist = arm(side, elbow, 0.25), hand_end = arm(side, wrist, 0.17);
    } else {  // hanging, a little out at the elbow, the hand in against the thigh
      elbow = sh + dvec3(side * 0.035, -0.28, 0);
      wrist = elbow + dvec3(side * -0.012, -0.25, 0);
      hand_end = wrist + dvec3(side * -0.02, -0.17, 0);
    }
    j.push_back({std::string("shoulder") + sfx, chest, clav, sh, true});
    j.push_back({std::string("upper_arm") + sfx, base, sh, elbow, true});
    j.push_back({std::string("forearm") + sfx, base + 1, elbow, wrist, true});
    j.push_back({std::string("hand") + sfx, base + 2, wrist, hand_end, true});
    if (shape.extras) add_fingers(j, side);
  }
  for (double side : {1.0, -1.0}) {
    const char* sfx = side > 0 ? ".L" : ".R";
    int base = static_cast<int>(j.size());
    dvec3 hip(side * 0.095, 0.92, 0), knee(side * 0.105, 0.50, 0.01), ankle(side * 0.11, 0.09, 0),
        toe(side * 0.11, 0.03, 0.13), toe_end(side * 0.11, 0.03, 0.2);
    if (shape.arms_down) {  // legs together: the thighs overlap along the inside, the knees touch
      hip = {side * 0.07, 0.92, 0}, knee = {side * 0.054, 0.50, 0.01}, ankle = {side * 0.06, 0.09, 0},
      toe = {side * 0.065, 0.03, 0.13}, toe_end = {side * 0.065, 0.03, 0.2};
    }
    j.push_back({std::string("thigh") + sfx, 0, hip, knee, false});
    j.push_back({std::string("shin") + sfx, base, knee, ankle, false});
    j.push_back({std::string("foot") + sfx, base + 1, ankle, toe, false});
    j.push_back({std::string("toes") + sfx, base + 2, toe, toe_end, false});
  }
  if (!shape.extras) return j;
  // The tail: from the back of the pelvis, backward and down, levelling out toward the tip.
  dvec3 p(0, 0.90, -0.06);
  for (int i = 0; i < kTailBones; ++i) {
    const double angle = (50.0 - 5.0 * i) * std::numbers::pi / 180.0;  // below the horizontal
    dvec3 next = p + 0.085 * dvec3(0, -std::sin(angle), -std::cos(angle));
    const std::string name = tail_bone_name(i);
    j.push_back({name, i == 0 ? 0 : static_cast<int>(j.size()) - 1, p, next, false,
                 0.04 - 0.03 * i / kTailBones, 0.04 - 0.03 * (i + 1) / kTailBones});
    p = next;
  }
  return j;
}

// A tapered capsule from a (radius ra) to b (radius rb), optionally flattened front to back.
struct Part {
  dvec3 a, b;
  double ra, rb;
  double depth = 1.0;  // z extent relative to x/y
  int bone;
  int group = 0;       // index into Body::groups (variants only)
};

double part_distance(const Part& p, dvec3 q) {
  if (p.depth != 1.0) {
    dvec3 mid = 0.5 * (p.a + p.b);
    q.z = mid.z + (q.z - mid.z) / p.depth;
  }
  dvec3 ab = p.b - p.a;
  double t = std::clamp(glm::dot(q - p.a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  double d = glm::length(q - (p.a + t * ab)) - (p.ra + t * (p.rb - p.ra));
  return p.depth < 1.0 ? d * p.depth : d;
}

constexpr double kBlend = 0.035;

// The variants' body is a tree of groups. The parts of a group are smoothly united (`blend`);
// a group is smoothly united with each child subtree on its own (`blend_to_parent` of the
// child), and those unions are combined by a plain minimum, so two subtrees that touch (a hand
// and a thigh, two fingers) meet in a crease instead of being webbed together.
constexpr size_t kMaxGroups = 32;  // body_sdf keeps them on the stack
struct Group {
  int parent;               // lower index, -1 for the root
  double blend;             // among the group's own parts
  double blend_to_parent;
};

struct Body {
  std::vector<Part> parts;
  std::vector<Group> groups;  // empty: one smooth union of every part (the default character)
  // Whether group a is group b or one of its ancestors, or the other way round: the skin blends
  // between them, so weights may diffuse across.
  bool related(int a, int b) const {
    if (a > b) std::swap(a, b);
    while (b > a) b = groups[b].parent;
    return a == b;
  }
};

// The quadruped's capsules: a barrel of a body, a neck and a muzzle, legs thinning to the paws.
std::vector<Part> quadruped_parts(const std::vector<JointSpec>& j,
                                  const std::function<int(const std::string&)>& idx) {
  std::vector<Part> parts;
  parts.push_back({{0, 0.625, -0.33}, {0, 0.63, -0.12}, 0.105, 0.11, 1.0, idx("hips")});
  parts.push_back({{0, 0.63, -0.10}, {0, 0.64, 0.12}, 0.11, 0.12, 1.0, idx("spine")});
  parts.push_back({{0, 0.635, 0.12}, {0, 0.64, 0.30}, 0.125, 0.115, 1.0, idx("chest")});
  parts.push_back({{0, 0.68, 0.31}, {0, 0.79, 0.44}, 0.07, 0.055, 1.0, idx("neck")});
  parts.push_back({{0, 0.81, 0.44}, {0, 0.78, 0.63}, 0.07, 0.035, 1.0, idx("head")});
  for (const char* s : {".L", ".R"}) {
    auto bone = [&](const std::string& n) { return idx(n + s); };
    auto capsule = [&](const char* n, double ra, double rb) {
      const JointSpec& b = j[bone(n)];
      parts.push_back({b.head, b.tail, ra, rb, 1.0, bone(n)});
    };
    capsule("shoulder", 0.055, 0.05);
    capsule("upper_arm", 0.048, 0.036);
    capsule("forearm", 0.032, 0.026);
    capsule("hand", 0.028, 0.026);
    capsule("thigh", 0.07, 0.045);
    capsule("shin", 0.04, 0.03);
    capsule("foot", 0.028, 0.026);
    capsule("toes", 0.028, 0.025);
  }
  return parts;
}

std::vector<Part> default_parts(const std::vector<JointSpec>& j, const Shape& shape,
                                const std::function<int(const std::string&)>& idx) {
  if (shape.quadruped) return quadruped_parts(j, idx);
  std::vector<Part> parts;
  if (!shape.arms_down)
    parts.push_back({{-0.075, 0.93, 0}, {0.075, 0.93, 0}, 0.115, 0.115, 0.8, idx("hips")});
  else  // a narrower pelvis over the closed legs
    parts.push_back({{-0.05, 0.93, 0}, {0.05, 0.93, 0}, 0.11, 0.11, 0.8, idx("hips")});
  parts.push_back({{0, 0.98, 0}, {0, 1.17, 0}, 0.115, 0.12, 0.75, idx("spine")});
  parts.push_back({{-0.055, 1.30, 0}, {0.055, 1.30, 0}, 0.135, 0.135, 0.72, idx("chest")});
  parts.push_back({{0, 1.22, 0}, {0, 1.38, 0}, 0.12, 0.11, 0.75, idx("chest")});
  parts.push_back({{0, 1.40, 0}, {0, 1.56, 0.005}, 0.055, 0.048, 1.0, idx("neck")});
  parts.push_back({{0, 1.62, 0.015}, {0, 1.69, 0.005}, 0.095, 0.09, 1.0, idx("head")});
  for (const char* s : {".L", ".R"}) {
    auto bone = [&](const std::string& n) { return idx(n + s); };
    const JointSpec& sh = j[bone("shoulder")];
    const JointSpec& ua = j[bone("upper_arm")];
    const JointSpec& fa = j[bone("forearm")];
    const JointSpec& hd = j[bone("hand")];
    parts.push_back({sh.head, sh.tail, 0.055, 0.058, 1.0, bone("shoulder")});
    parts.push_back({ua.head, ua.tail, 0.056, 0.044, 1.0, bone("upper_arm")});
    parts.push_back({fa.head, fa.tail, 0.043, 0.033, 1.0, bone("forearm")});
    if (!shape.extras) {
      parts.push_back({hd.head + 0.03 * glm::normalize(hd.tail - hd.head), hd.tail - 0.03 * glm::normalize(hd.tail - hd.head),
                       0.038, 0.03, 0.55, bone("hand")});
    } else {  // a shorter, broader palm that the fingers leave
      dvec3 u, w;
      hand_axes(hd, s[1] == 'L' ? 1.0 : -1.0, u, w);
      parts.push_back({hd.head + 0.025 * u, hd.head + 0.06 * u, 0.036, 0.034, 0.55, bone("hand")});
      dvec3 knuckles = hd.head + 0.074 * u;
      parts.push_back({knuckles - 0.026 * w, knuckles + 0.026 * w, 0.028, 0.028, 0.6, bone("hand")});
    }
    const JointSpec& th = j[bone("thigh")];
    const JointSpec& sn = j[bone("shin")];
    const JointSpec& ft = j[bone("foot")];
    const JointSpec& to = j[bone("toes")];
    parts.push_back({th.head, th.tail, 0.085, 0.057, 1.0, bone("thigh")});
    parts.push_back({sn.head, sn.tail + dvec3(0, 0.02, 0), 0.055, 0.04, 1.0, bone("shin")});
    parts.push_back({ft.head + dvec3(0, -0.02, -0.04), ft.tail, 0.045, 0.038, 1.0, bone("foot")});
    parts.push_back({to.head, to.tail, 0.036, 0.03, 1.0, bone("toes")});
  }
  return parts;
}

Body body_parts(const std::vector<JointSpec>& j, const Shape& shape) {
  auto idx = [&](const std::string& name) {
    for (size_t i = 0; i < j.size(); ++i)
      if (j[i].name == name) return static_cast<int>(i);
    return -1;
  };
  Body body;
  body.parts = default_parts(j, shape, idx);
  if (!shape.grouped()) return body;
  // Groups: 0 chest, spine, neck and head; 1 pelvis; 2, 3 the arms; 4, 5 the legs; 6 the tail;
  // then one per finger.
  enum { kTorso, kPelvis, kArmL, kArmR, kLegL, kLegR, kTail };
  body.groups = {{-1, kBlend, 0.0},        {kTorso, kBlend, kBlend}, {kTorso, kBlend, kBlend}, {kTorso, kBlend, kBlend},
                 {kPelvis, kBlend, kBlend}, {kPelvis, kBlend, kBlend}, {kPelvis, 0.006, kBlend}};
  for (Part& p : body.parts) {
    const std::string& n = j[p.bone].name;
    const bool left = n.ends_with(".L");
    if (n == "hips") p.group = kPelvis;
    else if (n.starts_with("thigh") || n.starts_with("shin") || n.starts_with("foot") || n.starts_with("toes"))
      p.group = left ? kLegL : kLegR;
    else if (n.ends_with(".L") || n.ends_with(".R"))
      p.group = left ? kArmL : kArmR;
    else
      p.group = kTorso;
  }
  if (!shape.extras && !shape.quadruped) return body;
  for (size_t b = 0; b < j.size(); ++b) {
    const JointSpec& s = j[b];
    const bool finger = s.name.starts_with("finger_");
    if (!finger && !s.name.starts_with("tail_")) continue;
    int group = kTail;
    dvec3 a = s.head;
    if (finger) {
      if (s.name[s.name.size() - 3] == '1') {  // a new finger: its own group under the arm
        body.groups.push_back({s.name.ends_with(".L") ? kArmL : kArmR, 0.004, 0.01});
        a -= 0.012 * glm::normalize(s.tail - s.head);  // from inside the palm
      }
      group = static_cast<int>(body.groups.size()) - 1;
    }
    body.parts.push_back({a, s.tail, s.r_head, s.r_tail, 1.0, static_cast<int>(b), group});
  }
  assert(body.groups.size() <= kMaxGroups);
  return body;
}

// Polynomial smooth minimum: equals min(a, b) when they differ by more than k.
double smooth_min(double a, double b, double k) {
  double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

double body_sdf(const Body& body, dvec3 q) {
  const std::vector<Part>& parts = body.parts;
  if (body.groups.empty()) {
    double d = part_distance(parts[0], q);
    for (size_t i = 1; i < parts.size(); ++i) d = smooth_min(d, part_distance(parts[i], q), kBlend);
    return d;
  }
  const size_t ng = body.groups.size();
  std::array<double, kMaxGroups> own, under;  // the group's parts; the min over its child subtrees
  std::array<bool, kMaxGroups> started{};
  own.fill(1e300);
  under.fill(1e300);
  for (const Part& p : parts) {
    double d = part_distance(p, q);
    own[p.group] = started[p.group] ? smooth_min(own[p.group], d, body.groups[p.group].blend) : d;
    started[p.group] = true;
  }
  for (size_t g = ng - 1; g > 0; --g) {  // children have higher indices than their parents
    double subtree = under[g] < 1e300 ? under[g] : own[g];
    int parent = body.groups[g].parent;
    under[parent] = std::min(under[parent], smooth_min(own[parent], subtree, body.groups[g].blend_to_parent));
  }
  return under[0] < 1e300 ? under[0] : own[0];
}

dvec3 sdf_gradient(const Body& parts, dvec3 q) {
  const double e = 1e-4;
  return dvec3(body_sdf(parts, q + dvec3(e, 0, 0)) - body_sdf(parts, q - dvec3(e, 0, 0)),
               body_sdf(parts, q + dvec3(0, e, 0)) - body_sdf(parts, q - dvec3(0, e, 0)),
               body_sdf(parts, q + dvec3(0, 0, e)) - body_sdf(parts, q - dvec3(0, 0, e))) /
         (2 * e);
}

struct Surface {
  std::vector<dvec3> positions;
  std::vector<Tri> triangles;
};

// Marching tetrahedra over the grid.
Surface polygonize(const Body& parts, double h) {
  dvec3 lo(1e300), hi(-1e300);
  for (const Part& p : parts.parts) {
    double r = std::max(p.ra, p.rb);
    lo = glm::min(lo, glm::min(p.a, p.b) - dvec3(r));
    hi = glm::max(hi, glm::max(p.a, p.b) + dvec3(r));
  }
  lo -= dvec3(2 * h);
  hi += dvec3(2 * h);
  const int nx = static_cast<int>(std::ceil((hi.x - lo.x) / h)) + 1;
  const int ny = static_cast<int>(std::ceil((hi.y - lo.y) / h)) + 1;
  const int nz = static_cast<int>(std::ceil((hi.z - lo.z) / h)) + 1;
  auto id = [&](int x, int y, int z) { return (static_cast<size_t>(z) * ny + y) * nx + x; };
  auto point = [&](size_t i) {
    int x = static_cast<int>(i % nx), y = static_cast<int>((i / nx) % ny), z = static_cast<int>(i / (size_t(nx) * ny));
    return lo + h * dvec3(x, y, z);
  };
  std::vector<double> f(size_t(nx) * ny * nz);
  tbb::parallel_for(0, nz, [&](int z) {
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        double v = body_sdf(parts, lo + h * dvec3(x, y, z));
        if (std::abs(v) < 1e-9) v = 1e-9;  // no grid value exactly on the surface
        f[id(x, y, z)] = v;
      }
  });
  Surface s;
  std::unordered_map<uint64_t, uint32_t> edge_vertex;
  auto vertex_on = [&](size_t a, size_t b) {
    if (a > b) std::swap(a, b);
    uint64_t key = static_cast<uint64_t>(a) * f.size() + b;
    auto [it, inserted] = edge_vertex.try_emplace(key, static_cast<uint32_t>(s.positions.size()));
    if (inserted) {
      double t = f[a] / (f[a] - f[b]);
      s.positions.push_back(point(a) + t * (point(b) - point(a)));
    }
    return it->second;
  };
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c, const dvec3& outward) {
    dvec3 n = glm::cross(s.positions[b] - s.positions[a], s.positions[c] - s.positions[a]);
    if (glm::dot(n, outward) < 0) std::swap(b, c);
    s.triangles.push_back({a, b, c});
  };
  static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int z = 0; z + 1 < nz; ++z)
    for (int y = 0; y + 1 < ny; ++y)
      for (int x = 0; x + 1 < nx; ++x) {
        size_t corner[8];
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
          corner[c] = id(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
          inside += f[corner[c]] < 0;
        }
        if (inside == 0 || inside == 8) continue;
        for (const auto& perm : kPerm) {
          // Kuhn simplex: 0 -> +e_a -> +e_a+e_b -> 7, shared diagonals match across cubes.
          int c1 = 1 << perm[0], c2 = c1 | (1 << perm[1]);
          size_t tet[4] = {corner[0], corner[c1], corner[c2], corner[7]};
          size_t in[4], out[4];
          int ni = 0, no = 0;
          for (size_t v : tet) (f[v] < 0 ? in[ni++] : out[no++]) = v;
          if (ni == 0 || no == 0) continue;
          dvec3 ci(0.0), co(0.0);
          for (int k = 0; k < ni; ++k) ci += point(in[k]);
          for (int k = 0; k < no; ++k) co += point(out[k]);
          dvec3 outward = co / double(no) - ci / double(ni);
          // New vertices are numbered in the order they are made, so the calls are sequenced (as
          // function arguments their order would be the compiler's: g++ made the committed demo
          // evaluating them last to first, which these keep)
          if (ni == 1) {
            const uint32_t c = vertex_on(in[0], out[2]), b = vertex_on(in[0], out[1]), a = vertex_on(in[0], out[0]);
            emit(a, b, c, outward);
          } else if (no == 1) {
            const uint32_t c = vertex_on(out[0], in[2]), b = vertex_on(out[0], in[1]), a = vertex_on(out[0], in[0]);
            emit(a, b, c, outward);
          } else {
            uint32_t q0 = vertex_on(in[0], out[0]), q1 = vertex_on(in[0], out[1]), q2 = vertex_on(in[1], out[1]),
                     q3 = vertex_on(in[1], out[0]);
            emit(q0, q1, q2, outward);
            emit(q0, q2, q3, outward);
          }
        }
      }
  return s;
}

// One-ring neighbours in CSR form, sorted (deterministic).
void vertex_neighbours(const Surface& s, std::vector<uint32_t>& start, std::vector<uint32_t>& adj) {
  std::vector<std::vector<uint32_t>> nb(s.positions.size());
  for (const Tri& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      nb[t[k]].push_back(t[(k + 1) % 3]);
      nb[t[k]].push_back(t[(k + 2) % 3]);
    }
  start.assign(1, 0);
  adj.clear();
  for (auto& n : nb) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    adj.insert(adj.end(), n.begin(), n.end());
    start.push_back(static_cast<uint32_t>(adj.size()));
  }
}

void relax(Surface& s, const Body& parts, int iterations) {
  std::vector<uint32_t> start, adj;
  vertex_neighbours(s, start, adj);
  std::vector<dvec3> next(s.positions.size());
  for (int it = 0; it < iterations; ++it) {
    tbb::parallel_for(size_t(0), s.positions.size(), [&](size_t v) {
      dvec3 p = s.positions[v];
      dvec3 c(0.0);
      for (uint32_t k = start[v]; k < start[v + 1]; ++k) c += s.positions[adj[k]];
      uint32_t n = start[v + 1] - start[v];
      if (n) c /= double(n);
      dvec3 g = sdf_gradient(parts, p);
      double gl = glm::length(g);
      dvec3 nrm = gl > 0 ? g / gl : dvec3(0.0);
      dvec3 d = c - p;
      p += 0.5 * (d - nrm * glm::dot(nrm, d));  // tangential move
      for (int newton = 0; newton < 2; ++newton) {  // back onto the zero set
        dvec3 gp = sdf_gradient(parts, p);
        double g2 = glm::dot(gp, gp);
        if (g2 > 1e-12) p -= body_sdf(parts, p) * gp / g2;
      }
      next[v] = p;
    });
    s.positions.swap(next);
  }
}

glm::dmat3 bone_frame(const JointSpec& j) {
  dvec3 y = glm::normalize(j.tail - j.head);
  dvec3 x;
  if (j.arm_frame) {
    x = glm::normalize(glm::cross(y, dvec3(0, 0, 1)));  // rotating +angle about x swings the bone forward
  } else {
    dvec3 hint(1, 0, 0);
    x = glm::normalize(hint - y * glm::dot(y, hint));
  }
  dvec3 z = glm::cross(x, y);
  return glm::dmat3(x, y, z);
}

glm::quat about(double degrees, glm::dvec3 axis) {
  return glm::quat(glm::angleAxis(degrees * std::numbers::pi / 180.0, glm::normalize(axis)));
}

// A LINEAR channel sampled at `keys` evenly spaced times over `duration`.
template <class F>
void add_rotation_channel(Clip& clip, const Skeleton& sk, uint32_t node, double duration, int keys, F angles) {
  AnimationSampler s;
  s.interpolation = Interpolation::kLinear;
  s.components = 4;
  for (int k = 0; k < keys; ++k) {
    double t = duration * k / (keys - 1);
    glm::quat q = glm::normalize(sk.node(node).rest.rotation * angles(t));
    s.times.push_back(static_cast<float>(t));
    s.values.insert(s.values.end(), {q.x, q.y, q.z, q.w});
  }
  clip.channels.push_back({node, ChannelPath::kRotation, static_cast<uint32_t>(clip.samplers.size())});
  clip.samplers.push_back(std::move(s));
}

Clip walk_clip(const Skeleton& sk, double unit) {
  Clip clip;
  clip.name = "walk";
  const double T = 1.0;
  const int keys = 31;
  const double two_pi = 2 * std::numbers::pi;
  auto phase = [&](double t) { return two_pi * t / T; };
  auto n = [&](const char* name) { return static_cast<uint32_t>(sk.find(name)); };
  for (int side = 0; side < 2; ++side) {
    const char* sfx = side == 0 ? ".L" : ".R";
    const double off = side == 0 ? 0.0 : std::numbers::pi;
    // Hip: 32 degrees forward / back (flexion is negative about the leg's local X).
    add_rotation_channel(clip, sk, n((std::string("thigh") + sfx).c_str()), T, keys,
                         [&](double t) { return about(-32.0 * std::sin(phase(t) + off), {1, 0, 0}); });
    // Knee: 8 to 68 degrees, bent most while the leg swings forward.
    add_rotation_channel(clip, sk, n((std::string("shin") + sfx).c_str()), T, keys, [&](double t) {
      double c = 0.5 + 0.5 * std::cos(phase(t) + off - 0.3);
      return about(8.0 + 60.0 * c * c, {1, 0, 0});
    });
    add_rotation_channel(clip, sk, n((std::string("foot") + sfx).c_str()), T, keys,
                         [&](double t) { return about(-12.0 * std::sin(phase(t) + off + 1.0), {1, 0, 0}); });
    // Arms swing against the legs; elbows bend a little more on the forward swing.
    add_rotation_channel(clip, sk, n((std::string("upper_arm") + sfx).c_str()), T, keys,
                         [&](double t) { return about(-28.0 * std::sin(phase(t) + off), {1, 0, 0}); });
    add_rotation_channel(clip, sk, n((std::string("forearm") + sfx).c_str()), T, keys,
                         [&](double t) { return about(25.0 - 15.0 * std::sin(phase(t) + off), {1, 0, 0}); });
  }
  add_rotation_channel(clip, sk, n("spine"), T, keys,
                       [&](double t) { return about(6.0 * std::sin(phase(t)), {0, 1, 0}); });
  add_rotation_channel(clip, sk, n("chest"), T, keys,
                       [&](double t) { return about(-8.0 * std::sin(phase(t)), {0, 1, 0}) * about(4.0, {1, 0, 0}); });
  // The hips bob twice per cycle.
  AnimationSampler bob;
  bob.interpolation = Interpolation::kLinear;
  bob.components = 3;
  const uint32_t hips = n("hips");
  const glm::vec3 rest = sk.node(hips).rest.translation;
  for (int k = 0; k < keys; ++k) {
    double t = T * k / (keys - 1);
    bob.times.push_back(static_cast<float>(t));
    bob.values.insert(bob.values.end(), {rest.x, static_cast<float>(rest.y - 0.015 * unit + 0.015 * unit * std::cos(2 * phase(t))), rest.z});
  }
  clip.channels.push_back({hips, ChannelPath::kTranslation, static_cast<uint32_t>(clip.samplers.size())});
  clip.samplers.push_back(std::move(bob));
  clip.duration = T;
  return clip;
}

Clip arm_raise_clip(const Skeleton& sk) {
  Clip clip;
  clip.name = "arm_raise";
  const double T = 2.0;
  const int keys = 61;
  auto up = [&](double t) { return rise_and_return(t, T); };
  auto n = [&](const std::string& name) { return static_cast<uint32_t>(sk.find(name)); };
  for (int side = 0; side < 2; ++side) {
    const std::string sfx = side == 0 ? ".L" : ".R";
    const double sign = side == 0 ? 1.0 : -1.0;  // abduction is +Z on the left, -Z on the right
    add_rotation_channel(clip, sk, n("shoulder" + sfx), T, keys,
                         [&](double t) { return about(sign * 15.0 * up(t), {0, 0, 1}); });
    add_rotation_channel(clip, sk, n("upper_arm" + sfx), T, keys,
                         [&](double t) { return about(sign * 125.0 * up(t), {0, 0, 1}); });
    add_rotation_channel(clip, sk, n("forearm" + sfx), T, keys, [&](double t) {
      double u = up(t);
      return about(110.0 * u * u, {1, 0, 0});
    });
    add_rotation_channel(clip, sk, n("hand" + sfx), T, keys,
                         [&](double t) { return about(20.0 * up(t), {1, 0, 0}); });
  }
  clip.duration = T;
  return clip;
}

// A travelling wave down the tail (each bone +-18 degrees about its local X, half a wavelength
// along the chain, so the tail curls up and down), and every finger phalanx curling 0 -> 70 -> 0.
Clip tail_wave_clip(const Skeleton& sk) {
  Clip clip;
  clip.name = "tail_wave";
  const double T = 2.0;
  const int keys = 61;
  const double two_pi = 2 * std::numbers::pi;
  for (int i = 0; i < kTailBones; ++i) {
    const std::string name = tail_bone_name(i);
    add_rotation_channel(clip, sk, static_cast<uint32_t>(sk.find(name)), T, keys, [&](double t) {
      return about(18.0 * std::sin(two_pi * t / T - i * std::numbers::pi / kTailBones), {1, 0, 0});
    });
  }
  auto curl = [&](double t) { return 0.5 - 0.5 * std::cos(two_pi * t / T); };
  for (const char* sfx : {".L", ".R"})
    for (const char* finger : {"thumb", "index", "middle", "ring", "little"})
      for (int k = 1; k <= 3; ++k) {
        std::string name = std::string("finger_") + finger + "_" + std::to_string(k) + sfx;
        add_rotation_channel(clip, sk, static_cast<uint32_t>(sk.find(name)), T, keys,
                             [&](double t) { return about(70.0 * curl(t), {1, 0, 0}); });
      }
  clip.duration = T;
  return clip;
}

// The quadruped's walk (1 s loop): a four-beat gait (left hind, left fore, right hind, right fore a
// quarter cycle apart), each upper leg swinging +-22 degrees, the lower leg folding on the forward
// swing; the spine sways, the head nods, the tail swings side to side.
Clip quadruped_walk_clip(const Skeleton& sk) {
  Clip clip;
  clip.name = "walk";
  const double T = 1.0;
  const int keys = 41;
  const double two_pi = 2 * std::numbers::pi;
  auto n = [&](const std::string& name) { return static_cast<uint32_t>(sk.find(name)); };
  struct Leg {
    const char* upper;
    const char* lower;
    const char* end;
    double phase;
  };
  const Leg legs[] = {{"thigh.L", "shin.L", "foot.L", 0.0},
                      {"upper_arm.L", "forearm.L", "hand.L", 0.25},
                      {"thigh.R", "shin.R", "foot.R", 0.5},
                      {"upper_arm.R", "forearm.R", "hand.R", 0.75}};
  for (const Leg& leg : legs) {
    const double off = two_pi * leg.phase;
    add_rotation_channel(clip, sk, n(leg.upper), T, keys,
                         [&](double t) { return about(-22.0 * std::sin(two_pi * t / T + off), {1, 0, 0}); });
    add_rotation_channel(clip, sk, n(leg.lower), T, keys, [&](double t) {
      const double c = 0.5 + 0.5 * std::cos(two_pi * t / T + off - 0.3);
      return about(5.0 + 55.0 * c * c, {1, 0, 0});
    });
    add_rotation_channel(clip, sk, n(leg.end), T, keys,
                         [&](double t) { return about(-15.0 * std::sin(two_pi * t / T + off + 1.0), {1, 0, 0}); });
  }
  add_rotation_channel(clip, sk, n("spine"), T, keys,
                       [&](double t) { return about(5.0 * std::sin(two_pi * t / T), {0, 1, 0}); });
  add_rotation_channel(clip, sk, n("neck"), T, keys,
                       [&](double t) { return about(6.0 * std::sin(2 * two_pi * t / T), {1, 0, 0}); });
  for (int i = 0; i < kQuadrupedTailBones; ++i) {
    const std::string name = tail_bone_name(i);
    add_rotation_channel(clip, sk, n(name), T, keys, [&](double t) {
      return about(12.0 * std::sin(two_pi * t / T - i * std::numbers::pi / kQuadrupedTailBones), {0, 0, 1});
    });
  }
  clip.duration = T;
  return clip;
}

// Sitting down and up again (2 s): the body tilts 35 degrees nose up about the hips, the hind legs
// fold under it (the haunch pressed against the belly, the hock at 115 degrees), the front legs stay
// upright, the tail curls down along the ground.
Clip quadruped_sit_clip(const Skeleton& sk) {
  Clip clip;
  clip.name = "sit";
  const double T = 2.0;
  const int keys = 61;
  auto u = [&](double t) { return rise_and_return(t, T); };
  auto n = [&](const std::string& name) { return static_cast<uint32_t>(sk.find(name)); };
  add_rotation_channel(clip, sk, n("hips"), T, keys, [&](double t) { return about(-35.0 * u(t), {1, 0, 0}); });
  for (const std::string sfx : {".L", ".R"}) {
    add_rotation_channel(clip, sk, n("thigh" + sfx), T, keys, [&](double t) { return about(-45.0 * u(t), {1, 0, 0}); });
    add_rotation_channel(clip, sk, n("shin" + sfx), T, keys, [&](double t) { return about(115.0 * u(t), {1, 0, 0}); });
    add_rotation_channel(clip, sk, n("foot" + sfx), T, keys, [&](double t) { return about(-60.0 * u(t), {1, 0, 0}); });
    add_rotation_channel(clip, sk, n("upper_arm" + sfx), T, keys, [&](double t) { return about(30.0 * u(t), {1, 0, 0}); });
    add_rotation_channel(clip, sk, n("forearm" + sfx), T, keys, [&](double t) { return about(5.0 * u(t), {1, 0, 0}); });
  }
  add_rotation_channel(clip, sk, n("neck"), T, keys, [&](double t) { return about(20.0 * u(t), {1, 0, 0}); });
  for (int i = 0; i < kQuadrupedTailBones; ++i) {
    const std::string name = tail_bone_name(i);
    add_rotation_channel(clip, sk, n(name), T, keys, [&](double t) { return about(12.0 * u(t), {1, 0, 0}); });
  }
  clip.duration = T;
  return clip;
}

}  // namespace

double demo_default_cell_size(DemoVariant variant) {
  const Shape shape = shape_of(variant);
  return shape.extras || shape.quadruped ? 0.011 : 0.015;
}

std::optional<DemoVariant> parse_demo_variant(std::string_view name) {
  if (name == "default") return DemoVariant::kDefault;
  if (name == "arms-down") return DemoVariant::kArmsDown;
  if (name == "tail") return DemoVariant::kTail;
  if (name == "arms-down+tail" || name == "tail+arms-down") return DemoVariant::kArmsDownTail;
  if (name == "quadruped") return DemoVariant::kQuadruped;
  return std::nullopt;
}

const char* demo_variant_name(DemoVariant variant) {
  switch (variant) {
    case DemoVariant::kDefault: return "default";
    case DemoVariant::kArmsDown: return "arms-down";
    case DemoVariant::kTail: return "tail";
    case DemoVariant::kArmsDownTail: return "arms-down+tail";
    case DemoVariant::kQuadruped: return "quadruped";
  }
  return "default";
}

Character make_demo_character(const DemoCharacterOptions& options) {
  const Shape shape = shape_of(options.variant);
  const double unit = options.unit_scale;  // scene units per metre
  const double cell = options.cell_size > 0 ? options.cell_size : demo_default_cell_size(options.variant);
  const std::vector<JointSpec> specs = joint_specs(shape);
  const size_t nj = specs.size();
  // Skeleton: joint nodes 0..nj-1, then the mesh node (a root, as glTF wants for skinned meshes).
  std::vector<glm::dmat3> frames(nj);
  for (size_t i = 0; i < nj; ++i) frames[i] = bone_frame(specs[i]);
  std::vector<SkeletonNode> nodes(nj + 1);
  for (size_t i = 0; i < nj; ++i) {
    SkeletonNode& n = nodes[i];
    n.name = specs[i].name;
    n.parent = specs[i].parent;
    glm::dmat3 parent_r = n.parent >= 0 ? frames[n.parent] : glm::dmat3(1.0);
    dvec3 parent_p = n.parent >= 0 ? specs[n.parent].head : dvec3(0.0);
    glm::dmat3 local_r = glm::transpose(parent_r) * frames[i];
    n.rest.rotation = glm::quat(glm::normalize(glm::quat_cast(local_r)));
    n.rest.translation = glm::vec3(unit * (glm::transpose(parent_r) * (specs[i].head - parent_p)));
  }
  nodes[nj].name = "body";
  Character c;
  c.source = "demo character (generated)";
  c.skeleton = Skeleton::create(std::move(nodes), "demo character").value();
  // Inverse bind matrices from the float rest pose the file will hold.
  Skin skin;
  skin.name = "rig";
  auto globals = c.skeleton.global_transforms(c.skeleton.rest_pose());
  for (size_t i = 0; i < nj; ++i) {
    skin.joints.push_back(static_cast<uint32_t>(i));
    skin.inverse_bind.push_back(glm::inverse(globals[i]));
  }
  c.skins.push_back(std::move(skin));

  // The skin surface (in metres).
  const Body body = body_parts(specs, shape);
  Surface s = polygonize(body, cell);
  relax(s, body, options.relax_iterations);

  // Weights: the nearest body part's bone, diffused over the surface (in the variants, only
  // between vertices of groups that blend, and only onto bones of related groups: not from a
  // hand into the thigh it touches).
  const size_t nv = s.positions.size();
  std::vector<float> w(nv * nj, 0.0f), w_next(nv * nj);
  std::vector<int> nearest_group(nv, 0);
  tbb::parallel_for(size_t(0), nv, [&](size_t v) {
    double best = 1e300;
    int bone = 0, group = 0;
    for (const Part& p : body.parts) {
      double d = part_distance(p, s.positions[v]);
      if (d < best) {
        best = d;
        bone = p.bone;
        group = p.group;
      }
    }
    w[v * nj + bone] = 1.0f;
    nearest_group[v] = group;
  });
  std::vector<uint32_t> start, adj;
  vertex_neighbours(s, start, adj);
  // allowed[g * nj + b]: whether bone b may weigh on a vertex of group g (its part's group is g,
  // an ancestor or a descendant): no weight of the touching hand on the thigh, of one finger on the next.
  std::vector<char> allowed;
  if (!body.groups.empty()) {
    std::vector<int> bone_group(nj, 0);
    for (const Part& p : body.parts) bone_group[p.bone] = p.group;
    allowed.resize(body.groups.size() * nj);
    for (size_t g = 0; g < body.groups.size(); ++g)
      for (size_t b = 0; b < nj; ++b) allowed[g * nj + b] = body.related(static_cast<int>(g), bone_group[b]);
    std::vector<uint32_t> kept_start(1, 0), kept;
    for (size_t v = 0; v < nv; ++v) {
      for (uint32_t k = start[v]; k < start[v + 1]; ++k)
        if (body.related(nearest_group[v], nearest_group[adj[k]])) kept.push_back(adj[k]);
      kept_start.push_back(static_cast<uint32_t>(kept.size()));
    }
    start.swap(kept_start);
    adj.swap(kept);
  }
  for (int it = 0; it < options.weight_smoothing_iterations; ++it) {
    tbb::parallel_for(size_t(0), nv, [&](size_t v) {
      uint32_t n = start[v + 1] - start[v];
      for (size_t b = 0; b < nj; ++b) {
        if (!allowed.empty() && !allowed[nearest_group[v] * nj + b]) {
          w_next[v * nj + b] = 0.0f;
          continue;
        }
        float sum = 0;
        for (uint32_t k = start[v]; k < start[v + 1]; ++k) sum += w[adj[k] * nj + b];
        w_next[v * nj + b] = n ? 0.5f * w[v * nj + b] + 0.5f * sum / float(n) : w[v * nj + b];
      }
    });
    w.swap(w_next);
  }
  Primitive prim;
  prim.mesh_name = "body";
  prim.node = static_cast<uint32_t>(nj);
  prim.skin = 0;
  prim.positions.resize(nv);
  for (size_t v = 0; v < nv; ++v) prim.positions[v] = glm::vec3(unit * s.positions[v]);
  prim.triangles = std::move(s.triangles);
  prim.influence_start.assign(1, 0);
  std::vector<std::pair<float, uint16_t>> inf;
  for (size_t v = 0; v < nv; ++v) {
    inf.clear();
    for (size_t b = 0; b < nj; ++b)
      if (w[v * nj + b] > 1e-3f) inf.emplace_back(w[v * nj + b], static_cast<uint16_t>(b));
    std::sort(inf.begin(), inf.end(), [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
    if (inf.size() > 4) inf.resize(4);
    float sum = 0;
    for (auto& e : inf) sum += e.first;
    for (auto& e : inf) {
      prim.influence_joint.push_back(e.second);
      prim.influence_weight.push_back(e.first / sum);
    }
    prim.influence_start.push_back(static_cast<uint32_t>(prim.influence_joint.size()));
  }
  c.primitives.push_back(std::move(prim));
  if (shape.quadruped) {
    c.clips.push_back(quadruped_walk_clip(c.skeleton));
    c.clips.push_back(quadruped_sit_clip(c.skeleton));
    return c;
  }
  c.clips.push_back(walk_clip(c.skeleton, unit));
  c.clips.push_back(arm_raise_clip(c.skeleton));
  if (shape.extras) c.clips.push_back(tail_wave_clip(c.skeleton));
  return c;
}

}  // namespace cagewrap
