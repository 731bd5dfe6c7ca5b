#pragma once
/// @file
/// Keyframe animation (glTF 2.0's model): samplers of key times and values, channels that drive a
/// node's translation, rotation, scale or a geometry's morph weights, and a player that mixes
/// animations in the update traversal. Nothing here touches GL.
#include "sgfx/Export.h"
#include "sgfx/Group.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

class Geometry;

/// How a sampler fills the time between keys (glTF 2.0, animation.sampler.interpolation).
enum class Interpolation : std::uint8_t { Step, Linear, CubicSpline };
/// What a channel drives (glTF 2.0, animation.channel.target.path).
enum class AnimationPath : std::uint8_t { Translation, Rotation, Scale, Weights };

/// Key times (seconds, strictly increasing) and values, `components` floats per value. Rotations
/// are quaternions stored x, y, z, w (glTF's order). CubicSpline stores three values per key, as
/// glTF does: in-tangent, value, out-tangent.
struct SGFX_API AnimationSampler {
    std::vector<float> times;
    std::vector<float> values;
    std::size_t components = 3;
    Interpolation interpolation = Interpolation::Linear;

    /// Throws std::invalid_argument with a message that says what is wrong ("times not increasing
    /// at key 3", "12 values for 4 keys of 3 components", "NaN at value 5", "no keys"); the caller
    /// prefixes the element (`animations[0].samplers[2].input`).
    void validate() const;
    /// The value at time t into out[0..components). Before the first key: the first value; after
    /// the last: the last one (glTF). `rotation`: slerp by the shortest path (Linear), result
    /// normalised (every mode).
    void sample(float t, float* out, bool rotation = false) const;
    float startTime() const { return times.empty() ? 0.0f : times.front(); }
    float endTime() const { return times.empty() ? 0.0f : times.back(); }
};

/// A node an animation drives, with its rest pose: the paths no active channel drives keep it.
struct SGFX_API AnimationTarget {
    std::weak_ptr<Transform> transform;          ///< translation, rotation, scale channels
    std::vector<std::weak_ptr<Geometry>> morphs; ///< weights channels: every primitive of the mesh
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 scale{1.0f};
    std::vector<float> weights; ///< rest morph weights (the node's or the mesh's)
    std::string name;           ///< for messages
    /// The mixed morph weights AnimationPlayer::apply() wrote last (the rest weights when no
    /// channel drives them).
    std::vector<float> currentWeights;
};

/// One channel: sampler `sampler` of its animation drives `path` of target `target` (an index into
/// AnimationPlayer::targets).
struct SGFX_API AnimationChannel {
    std::size_t sampler = 0;
    std::size_t target = 0;
    AnimationPath path = AnimationPath::Translation;
};

/// A named set of channels played together.
struct SGFX_API Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    /// The last key time of all samplers (0 when empty).
    float duration() const;
};

/// Plays a model's animations on its targets: play, pause, seek, loop or clamp, speed, a weight
/// per animation and cross-fades. Time is a function of the simulation time passed to update()
/// (anchored at each call that changes the state, never accumulated per frame), so machines
/// that replay the same calls at the same simulation times make the same pose.
class SGFX_API AnimationPlayer {
public:
    enum class Wrap : std::uint8_t { Loop, Clamp };

    std::vector<AnimationTarget> targets;
    std::vector<Animation> animations;

    /// The animation named `name`, or -1.
    int find(std::string_view name) const;

    /// Starts animation `index` from its start (its end when the speed is negative) at weight 1
    /// and stops the others (weight 0). Throws std::out_of_range naming the index and the count.
    /// Like every call that changes the state, it takes effect at the last update's simulation
    /// time.
    void play(std::size_t index);
    void pause();  ///< freezes every animation's time, and the fades
    void resume(); ///< continues from where pause() left them
    bool playing() const { return playing_; }
    /// Sets the current animation's time (seconds into it). Throws std::invalid_argument on NaN or
    /// infinity, std::logic_error when no animation was played.
    void seek(double seconds);
    /// Time scale (negative plays backwards); throws std::invalid_argument on NaN or infinity.
    void setSpeed(double speed);
    double speed() const { return speed_; }
    /// Loop or Clamp from the present time on (the times are re-anchored, so nothing jumps).
    void setWrap(Wrap w);
    Wrap wrap() const { return wrap_; }
    /// Weight of animation `index` in the mix (0..1); several animations may play at once. Throws
    /// std::invalid_argument on NaN, infinity or a negative weight.
    void setWeight(std::size_t index, float weight);
    float weight(std::size_t index) const;
    /// Fades from the present mix to animation `index` (started from its start) over `seconds`:
    /// its weight rises linearly from 0 to 1 while the others fall to 0 (seconds of simulation
    /// time; 0 switches at once; NaN, infinite or negative: std::invalid_argument).
    void crossFade(std::size_t index, double seconds);
    /// The time within animation `index` at the last update (after wrapping).
    double time(std::size_t index) const;
    /// The index of the animation play() or crossFade() chose last, or -1.
    int current() const { return current_; }

    /// Advances to `simulationTime` (UpdateVisitor::simulationTime) and writes the pose into
    /// the targets' transforms and geometries.
    void update(double simulationTime);
    /// Writes the pose at the present times and weights (update() calls it).
    void apply();

private:
    /// One animation's clock and weight. Both are functions of the simulation time: the time runs
    /// from anchorTime at anchorSim_, the weight fades linearly from `weight` at fadeStart.
    struct Track {
        double anchorTime = 0.0;    ///< animation time at anchorSim_ (wrapped)
        float weight = 0.0f;        ///< weight at fadeStart
        float targetWeight = 0.0f;  ///< weight after the fade
        double fadeStart = 0.0;     ///< simulation time the fade began
        double fadeSeconds = 0.0;   ///< 0: no fade
        double time = 0.0;          ///< after the last update, wrapped
        float currentWeight = 0.0f; ///< after the last update
    };
    /// apply()'s sums for one target, kept between calls so that apply() does not allocate.
    struct TargetMix {
        glm::vec3 translation{0.0f};
        glm::vec4 rotation{0.0f};
        glm::vec4 firstRotation{0.0f}; ///< the hemisphere the others are aligned to
        glm::vec3 scale{0.0f};
        float translationWeight = 0.0f, rotationWeight = 0.0f, scaleWeight = 0.0f, weightsWeight = 0.0f;
        std::size_t weightsOffset = 0, weightsCount = 0; ///< into weightSums_
    };
    std::vector<Track> tracks_;
    std::vector<TargetMix> mix_;
    std::vector<float> weightSums_;
    std::vector<float> sampled_; ///< one sampled value
    double anchorSim_ = 0.0;     ///< simulation time the anchors refer to
    double lastSim_ = 0.0;       ///< simulation time of the last update
    double speed_ = 1.0;
    Wrap wrap_ = Wrap::Loop;
    bool playing_ = false;
    bool posed_ = false; ///< the last update wrote a pose with a weight > 0
    int current_ = -1;
    void reanchor(); ///< moves every anchor to lastSim_
    Track& track(std::size_t index);
    const Track& track(std::size_t index) const;
    void syncTracks();         ///< one track per animation
    void evaluate(double sim); ///< each track's time and weight at `sim`
    double trackTime(const Track& tr, std::size_t index, double sim) const;
    float trackWeight(const Track& tr, double sim) const;
    void accumulate(std::size_t index); ///< adds animation `index` to mix_
    void writePose();
};

/// A Group that plays its animations in the update traversal: what the glTF loader returns for a
/// file with animations. Its update runs the player before the children are visited.
class SGFX_API AnimatedGroup : public Group {
public:
    static std::shared_ptr<AnimatedGroup> create() { return std::make_shared<AnimatedGroup>(); }
    AnimatedGroup();
    AnimationPlayer& player() { return *player_; }
    const std::shared_ptr<AnimationPlayer>& playerPtr() const { return player_; }

private:
    std::shared_ptr<AnimationPlayer> player_;
};

/// The player of `node` when it is an AnimatedGroup, else null.
SGFX_API AnimationPlayer* animationPlayer(Node& node);

} // namespace sgfx
