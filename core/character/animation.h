// Animation clips as glTF stores them: keyframed samplers driving node translation, rotation,
// scale and morph weights, sampled at any time with STEP, LINEAR (slerp for rotations) or
// CUBICSPLINE (Hermite) interpolation (glTF 2.0 specification, Appendix C), plus a player for
// play, loop and scrub.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/character/skeleton.h"

namespace cagewrap {

enum class Interpolation { kStep, kLinear, kCubicSpline };
enum class ChannelPath { kTranslation, kRotation, kScale, kWeights };

const char* interpolation_name(Interpolation i);
const char* channel_path_name(ChannelPath p);

struct AnimationSampler {
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<float> times;   // #K key times in seconds, increasing
  std::vector<float> values;  // #K x C, or #K x 3 x C for CUBICSPLINE (in-tangent, value, out-tangent)
  uint32_t components = 0;    // C: 3 (translation, scale), 4 (rotation x, y, z, w), #targets (weights)
  size_t num_keys() const { return times.size(); }
};

struct AnimationChannel {
  uint32_t node = 0;
  ChannelPath path = ChannelPath::kTranslation;
  uint32_t sampler = 0;
};

struct Clip {
  std::string name;
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  double duration = 0.0;  // the last key time over all samplers
};

// The sampler's value at time t (clamped to its first/last key) into out (C values).
// Rotations (x, y, z, w) are interpolated along the shortest arc and returned unit length.
void sample(const AnimationSampler& sampler, double t, bool is_rotation, std::span<float> out);

// Writes every channel of the clip, sampled at time t, into the pose (nodes the clip does not
// animate keep what the pose had).
void apply_clip(const Clip& clip, double t, Pose& pose);

// Clip-local time: wrapped into [0, duration) when looping, otherwise clamped to [0, duration].
double clip_time(double t, double duration, bool loop);

// Playback state for one clip: play/pause, loop, speed, scrub.
class ClipPlayer {
 public:
  explicit ClipPlayer(double duration = 0.0) : duration_(duration) {}
  void play() { playing_ = true; }
  void pause() { playing_ = false; }
  void set_loop(bool loop) { loop_ = loop; }
  void set_speed(double speed) { speed_ = speed; }
  // Jumps to a time (clamped or wrapped like playback).
  void scrub(double t) { time_ = clip_time(t, duration_, loop_); }
  // Advances by dt seconds of wall time while playing; a non-looping clip stops at its end.
  void advance(double dt);
  double time() const { return time_; }
  bool playing() const { return playing_; }
  bool looping() const { return loop_; }
  double duration() const { return duration_; }

 private:
  double duration_ = 0.0;
  double time_ = 0.0;
  double speed_ = 1.0;
  bool playing_ = false;
  bool loop_ = true;
};

}  // namespace cagewrap
