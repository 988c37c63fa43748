#include "core/character/animation.h"

#include <algorithm>
#include <cmath>

namespace cagewrap {

const char* interpolation_name(Interpolation i) {
  switch (i) {
    case Interpolation::kStep: return "STEP";
    case Interpolation::kLinear: return "LINEAR";
    case Interpolation::kCubicSpline: return "CUBICSPLINE";
  }
  return "?";
}

const char* channel_path_name(ChannelPath p) {
  switch (p) {
    case ChannelPath::kTranslation: return "translation";
    case ChannelPath::kRotation: return "rotation";
    case ChannelPath::kScale: return "scale";
    case ChannelPath::kWeights: return "weights";
  }
  return "?";
}

static void normalize_quat(std::span<float> q) {
  double n = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
  if (n > 0)
    for (int c = 0; c < 4; ++c) q[c] = static_cast<float>(q[c] / n);
}

// Spherical interpolation of (x, y, z, w) quaternions along the shortest arc.
static void slerp(const float* a, const float* b, double u, std::span<float> out) {
  double dot = 0;
  for (int c = 0; c < 4; ++c) dot += double(a[c]) * b[c];
  double sign = 1.0;
  if (dot < 0) {
    dot = -dot;
    sign = -1.0;
  }
  double wa, wb;
  if (dot > 0.9995) {  // nearly parallel: lerp, then normalize
    wa = 1.0 - u;
    wb = u;
  } else {
    double theta = std::acos(std::min(dot, 1.0));
    double s = std::sin(theta);
    wa = std::sin((1.0 - u) * theta) / s;
    wb = std::sin(u * theta) / s;
  }
  for (int c = 0; c < 4; ++c) out[c] = static_cast<float>(wa * a[c] + sign * wb * b[c]);
  normalize_quat(out);
}

void sample(const AnimationSampler& s, double t, bool is_rotation, std::span<float> out) {
  const size_t k = s.num_keys();
  const uint32_t c = s.components;
  if (k == 0 || c == 0) return;
  const bool cubic = s.interpolation == Interpolation::kCubicSpline;
  // Element e of key i: value at (i*stride + offset + e).
  const size_t stride = cubic ? 3 * c : c;
  const size_t value_offset = cubic ? c : 0;
  auto value = [&](size_t i) { return s.values.data() + i * stride + value_offset; };
  if (k == 1 || t <= s.times.front()) {
    std::copy_n(value(0), c, out.begin());
  } else if (t >= s.times.back()) {
    std::copy_n(value(k - 1), c, out.begin());
  } else {
    // Key i with times[i] <= t < times[i+1].
    size_t i = static_cast<size_t>(std::upper_bound(s.times.begin(), s.times.end(), static_cast<float>(t)) -
                                   s.times.begin());
    i = std::clamp<size_t>(i, 1, k - 1) - 1;
    double t0 = s.times[i], t1 = s.times[i + 1];
    double dt = t1 - t0;
    double u = dt > 0 ? std::clamp((t - t0) / dt, 0.0, 1.0) : 0.0;
    switch (s.interpolation) {
      case Interpolation::kStep:
        std::copy_n(value(i), c, out.begin());
        break;
      case Interpolation::kLinear:
        if (is_rotation && c == 4) {
          slerp(value(i), value(i + 1), u, out);
        } else {
          for (uint32_t e = 0; e < c; ++e) out[e] = static_cast<float>((1.0 - u) * value(i)[e] + u * value(i + 1)[e]);
        }
        break;
      case Interpolation::kCubicSpline: {
        const float* p0 = value(i);
        const float* m0 = s.values.data() + i * stride + 2 * c;  // out-tangent of key i
        const float* p1 = value(i + 1);
        const float* m1 = s.values.data() + (i + 1) * stride;  // in-tangent of key i+1
        double u2 = u * u, u3 = u2 * u;
        double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
        for (uint32_t e = 0; e < c; ++e)
          out[e] = static_cast<float>(h00 * p0[e] + h10 * dt * m0[e] + h01 * p1[e] + h11 * dt * m1[e]);
        break;
      }
    }
  }
  if (is_rotation && c == 4) normalize_quat(out);
}

void apply_clip(const Clip& clip, double t, Pose& pose) {
  float buf[4];
  std::vector<float> weights;
  for (const AnimationChannel& ch : clip.channels) {
    const AnimationSampler& s = clip.samplers[ch.sampler];
    if (ch.node >= pose.local.size()) continue;
    Trs& trs = pose.local[ch.node];
    switch (ch.path) {
      case ChannelPath::kTranslation:
        if (s.components != 3) break;
        sample(s, t, false, buf);
        trs.translation = {buf[0], buf[1], buf[2]};
        break;
      case ChannelPath::kScale:
        if (s.components != 3) break;
        sample(s, t, false, buf);
        trs.scale = {buf[0], buf[1], buf[2]};
        break;
      case ChannelPath::kRotation:
        if (s.components != 4) break;
        sample(s, t, true, buf);
        trs.rotation = glm::quat(buf[3], buf[0], buf[1], buf[2]);
        break;
      case ChannelPath::kWeights:
        if (pose.morph_weights.size() < pose.local.size()) pose.morph_weights.resize(pose.local.size());
        pose.morph_weights[ch.node].resize(s.components);
        sample(s, t, false, pose.morph_weights[ch.node]);
        break;
    }
  }
}

double clip_time(double t, double duration, bool loop) {
  if (!(duration > 0)) return 0.0;
  if (!std::isfinite(t)) return 0.0;
  if (loop) {
    double w = std::fmod(t, duration);
    if (w < 0) w += duration;
    return w >= duration ? 0.0 : w;
  }
  return std::clamp(t, 0.0, duration);
}

void ClipPlayer::advance(double dt) {
  if (!playing_) return;
  double t = time_ + dt * speed_;
  if (!loop_ && (t >= duration_ || t <= 0.0)) playing_ = false;
  time_ = clip_time(t, duration_, loop_);
}

}  // namespace cagewrap
