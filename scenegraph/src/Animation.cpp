#include "sgfx/Animation.h"
#include "sgfx/Geometry.h"

#include "sgfx/Visitors.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

// Shortest round-trip text of a float, so "0.5 after 0.5" shows the values that compare.
std::string text(float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string count(std::size_t n) {
    return std::to_string(n);
}

void copyValue(const float* from, std::size_t n, float* out) {
    std::copy(from, from + n, out);
}

// Normalises x, y, z, w in place; a zero quaternion becomes the identity.
void normaliseQuat(float* q) {
    const float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(len > 1e-20f)) {
        q[0] = q[1] = q[2] = 0.0f;
        q[3] = 1.0f;
        return;
    }
    for (int i = 0; i < 4; ++i)
        q[i] /= len;
}

// Spherical interpolation by the shortest arc (glTF 2.0 Appendix C, "Spherical linear").
void slerp(const float* a, const float* b, float s, float* out) {
    float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    const float sign = d < 0.0f ? -1.0f : 1.0f; // q and -q are the same rotation: take the short arc
    d *= sign;
    float wa = 1.0f - s, wb = s;
    if (d < 0.9995f) { // else nearly parallel: sin(theta) ~ 0, the linear weights are as good
        const float theta = std::acos(std::min(d, 1.0f));
        const float sinTheta = std::sin(theta);
        wa = std::sin((1.0f - s) * theta) / sinTheta;
        wb = std::sin(s * theta) / sinTheta;
    }
    for (int i = 0; i < 4; ++i)
        out[i] = wa * a[i] + wb * sign * b[i];
}

double wrapTime(double t, double duration, AnimationPlayer::Wrap wrap) {
    if (!(duration > 0.0)) return 0.0;
    if (wrap == AnimationPlayer::Wrap::Clamp) return std::clamp(t, 0.0, duration);
    double r = std::fmod(t, duration);
    if (r < 0.0) r += duration;
    return r < duration ? r : 0.0; // -tiny + duration may round to duration
}

void checkIndex(const char* what, std::size_t index, std::size_t n) {
    if (index >= n)
        throw std::out_of_range(std::string("AnimationPlayer::") + what + ": animation index " +
                                count(index) + " out of range (" + count(n) + " animations)");
}

void checkFinite(const char* what, double v, bool nonNegative) {
    if (!std::isfinite(v) || (nonNegative && v < 0.0))
        throw std::invalid_argument(std::string("AnimationPlayer::") + what + ": " + std::to_string(v) +
                                    (nonNegative ? " is not a finite value >= 0" : " is not finite"));
}

glm::vec4 toVec4(const glm::quat& q) {
    return {q.x, q.y, q.z, q.w};
}

} // namespace

// ---------------------------------------------------------------- AnimationSampler
void AnimationSampler::validate() const {
    if (components < 1) throw std::invalid_argument("components must be at least 1 (0)");
    if (times.empty()) throw std::invalid_argument("no keys");
    for (std::size_t k = 0; k < times.size(); ++k) {
        if (!std::isfinite(times[k])) throw std::invalid_argument("NaN or infinite time at key " + count(k));
        if (k == 0 && times[k] < 0.0f)
            throw std::invalid_argument("negative time at key 0 (" + text(times[k]) + ")");
        if (k > 0 && !(times[k] > times[k - 1]))
            throw std::invalid_argument("times not increasing at key " + count(k) + " (" + text(times[k]) +
                                        " after " + text(times[k - 1]) + ")");
    }
    const bool cubic = interpolation == Interpolation::CubicSpline;
    const std::size_t expected = times.size() * components * (cubic ? 3 : 1);
    if (values.size() != expected)
        throw std::invalid_argument(
            count(values.size()) + " values for " + count(times.size()) + " keys of " + count(components) +
            " components (" + count(expected) + " expected" +
            (cubic ? ": CubicSpline has in-tangent, value, out-tangent per key)" : ")"));
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i])) throw std::invalid_argument("NaN or infinite value at " + count(i));
}

void AnimationSampler::sample(float t, float* out, bool rotation) const {
    const std::size_t n = components, keys = times.size();
    const bool cubic = interpolation == Interpolation::CubicSpline;
    const std::size_t stride = cubic ? 3 * n : n, offset = cubic ? n : 0; // CubicSpline: a_k, v_k, b_k
    const bool quat = rotation && n == 4;
    if (n == 0) return;
    if (keys == 0 || values.size() < keys * stride) { // invalid (validate() says why): a neutral value
        std::fill(out, out + n, 0.0f);
        if (quat) out[3] = 1.0f;
        return;
    }
    const float* v = values.data();
    if (keys == 1 || !(t > times.front())) { // before the first key (or NaN): the first value
        copyValue(v + offset, n, out);
    } else if (!(t < times.back())) {
        copyValue(v + (keys - 1) * stride + offset, n, out);
    } else {
        const std::size_t k1 = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin());
        const std::size_t k = k1 - 1; // times[k] <= t < times[k1]
        const float td = times[k1] - times[k];
        const float s = td > 0.0f ? (t - times[k]) / td : 0.0f;
        const float* vk = v + k * stride + offset;
        const float* vk1 = v + k1 * stride + offset;
        switch (interpolation) {
        case Interpolation::Step:
            copyValue(vk, n, out);
            break;
        case Interpolation::Linear:
            if (quat) {
                slerp(vk, vk1, s, out);
            } else {
                for (std::size_t i = 0; i < n; ++i)
                    out[i] = vk[i] + s * (vk1[i] - vk[i]);
            }
            break;
        case Interpolation::CubicSpline: {
            // Hermite spline with tangents scaled by the key interval (glTF 2.0 Appendix C).
            const float* bk = vk + n;   // out-tangent of key k
            const float* ak1 = vk1 - n; // in-tangent of key k + 1
            const float s2 = s * s, s3 = s2 * s;
            const float h00 = 2.0f * s3 - 3.0f * s2 + 1.0f, h10 = (s3 - 2.0f * s2 + s) * td;
            const float h01 = -2.0f * s3 + 3.0f * s2, h11 = (s3 - s2) * td;
            for (std::size_t i = 0; i < n; ++i)
                out[i] = h00 * vk[i] + h10 * bk[i] + h01 * vk1[i] + h11 * ak1[i];
            break;
        }
        }
    }
    if (quat) normaliseQuat(out);
}

float Animation::duration() const {
    float d = 0.0f;
    for (const AnimationSampler& s : samplers)
        d = std::max(d, s.endTime());
    return d;
}

// ---------------------------------------------------------------- AnimationPlayer: clock
int AnimationPlayer::find(std::string_view name) const {
    for (std::size_t i = 0; i < animations.size(); ++i)
        if (animations[i].name == name) return int(i);
    return -1;
}

void AnimationPlayer::syncTracks() {
    if (tracks_.size() != animations.size()) tracks_.resize(animations.size());
}

AnimationPlayer::Track& AnimationPlayer::track(std::size_t index) {
    syncTracks();
    checkIndex("track", index, animations.size());
    return tracks_[index];
}

const AnimationPlayer::Track& AnimationPlayer::track(std::size_t index) const {
    static const Track idle; // an animation added since the last call: not started
    checkIndex("track", index, animations.size());
    return index < tracks_.size() ? tracks_[index] : idle;
}

double AnimationPlayer::trackTime(const Track& tr, std::size_t index, double sim) const {
    // A function of the simulation time, never a per-frame sum: replays make the same times.
    const double t = playing_ ? tr.anchorTime + (sim - anchorSim_) * speed_ : tr.anchorTime;
    return wrapTime(t, animations[index].duration(), wrap_);
}

float AnimationPlayer::trackWeight(const Track& tr, double sim) const {
    if (!(tr.fadeSeconds > 0.0) || !playing_) return tr.weight; // fades pause with the clock
    const double f = (sim - tr.fadeStart) / tr.fadeSeconds;
    if (f >= 1.0) return tr.targetWeight;
    if (!(f > 0.0)) return tr.weight;
    return float(tr.weight + (tr.targetWeight - tr.weight) * f);
}

void AnimationPlayer::reanchor() {
    syncTracks();
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
        Track& tr = tracks_[i];
        const double t = trackTime(tr, i, lastSim_);
        const float w = trackWeight(tr, lastSim_);
        double remaining = 0.0;
        if (tr.fadeSeconds > 0.0)
            remaining = playing_ ? tr.fadeSeconds - std::max(0.0, lastSim_ - tr.fadeStart) : tr.fadeSeconds;
        tr.anchorTime = t;
        tr.weight = w;
        if (remaining > 0.0) {
            tr.fadeStart = lastSim_;
            tr.fadeSeconds = remaining;
        } else {
            tr.fadeSeconds = 0.0;
            tr.targetWeight = w;
        }
    }
    anchorSim_ = lastSim_;
}

void AnimationPlayer::evaluate(double sim) {
    syncTracks();
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
        tracks_[i].time = trackTime(tracks_[i], i, sim);
        tracks_[i].currentWeight = trackWeight(tracks_[i], sim);
    }
}

void AnimationPlayer::play(std::size_t index) {
    syncTracks();
    checkIndex("play", index, animations.size());
    reanchor();
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
        Track& tr = tracks_[i];
        tr.weight = tr.targetWeight = i == index ? 1.0f : 0.0f;
        tr.fadeSeconds = 0.0;
    }
    // Backwards play starts at the end.
    tracks_[index].anchorTime = speed_ < 0.0 ? double(animations[index].duration()) : 0.0;
    playing_ = true;
    current_ = int(index);
    evaluate(lastSim_);
}

void AnimationPlayer::pause() {
    if (!playing_) return;
    reanchor();
    playing_ = false;
    evaluate(lastSim_);
}

void AnimationPlayer::resume() {
    if (playing_) return;
    reanchor(); // paused: the anchors stay, the remaining fades restart from now
    playing_ = true;
    evaluate(lastSim_);
}

void AnimationPlayer::seek(double seconds) {
    checkFinite("seek", seconds, false);
    if (current_ < 0)
        throw std::logic_error("AnimationPlayer::seek: no current animation (play() one first)");
    reanchor();
    track(std::size_t(current_)).anchorTime = seconds;
    evaluate(lastSim_);
}

void AnimationPlayer::setWrap(Wrap w) {
    reanchor();
    wrap_ = w;
    evaluate(lastSim_);
}

void AnimationPlayer::setSpeed(double speed) {
    checkFinite("setSpeed", speed, false);
    reanchor();
    speed_ = speed;
    evaluate(lastSim_);
}

void AnimationPlayer::setWeight(std::size_t index, float weight) {
    syncTracks();
    checkIndex("setWeight", index, animations.size());
    checkFinite("setWeight", weight, true);
    reanchor();
    Track& tr = tracks_[index];
    tr.weight = tr.targetWeight = weight;
    tr.fadeSeconds = 0.0;
    evaluate(lastSim_);
}

float AnimationPlayer::weight(std::size_t index) const {
    return track(index).currentWeight;
}

double AnimationPlayer::time(std::size_t index) const {
    return track(index).time;
}

void AnimationPlayer::crossFade(std::size_t index, double seconds) {
    syncTracks();
    checkIndex("crossFade", index, animations.size());
    checkFinite("crossFade", seconds, true);
    if (seconds == 0.0) return play(index); // a hard switch
    reanchor();
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
        Track& tr = tracks_[i];
        tr.targetWeight = i == index ? 1.0f : 0.0f;
        if (i == index) tr.weight = 0.0f;
        tr.fadeStart = lastSim_;
        tr.fadeSeconds = tr.weight == tr.targetWeight ? 0.0 : seconds;
    }
    tracks_[index].anchorTime = speed_ < 0.0 ? double(animations[index].duration()) : 0.0;
    playing_ = true;
    current_ = int(index);
    evaluate(lastSim_);
}

void AnimationPlayer::update(double simulationTime) {
    checkFinite("update", simulationTime, false);
    lastSim_ = simulationTime;
    evaluate(simulationTime);
    bool any = false;
    for (const Track& tr : tracks_)
        any = any || tr.currentWeight > 0.0f;
    // Once more after the last weight reached 0, so the targets return to their rest pose.
    if (any || posed_) apply();
    posed_ = any;
}

// ---------------------------------------------------------------- AnimationPlayer: pose
void AnimationPlayer::apply() {
    syncTracks();
    mix_.assign(targets.size(), TargetMix{});
    // Morph weight counts: the rest weights', or more when a playing channel has more.
    for (std::size_t k = 0; k < targets.size(); ++k)
        mix_[k].weightsCount = targets[k].weights.size();
    for (std::size_t a = 0; a < animations.size(); ++a) {
        if (!(tracks_[a].currentWeight > 0.0f)) continue;
        for (const AnimationChannel& c : animations[a].channels)
            if (c.path == AnimationPath::Weights && c.target < targets.size() &&
                c.sampler < animations[a].samplers.size())
                mix_[c.target].weightsCount =
                    std::max(mix_[c.target].weightsCount, animations[a].samplers[c.sampler].components);
    }
    std::size_t total = 0;
    for (TargetMix& m : mix_) {
        m.weightsOffset = total;
        total += m.weightsCount;
    }
    weightSums_.assign(total, 0.0f);
    // Tracks at weight 0 are not sampled.
    for (std::size_t a = 0; a < animations.size(); ++a)
        if (tracks_[a].currentWeight > 0.0f) accumulate(a);
    writePose();
}

void AnimationPlayer::accumulate(std::size_t index) {
    const Animation& a = animations[index];
    const float w = tracks_[index].currentWeight;
    const float t = float(tracks_[index].time);
    for (const AnimationChannel& c : a.channels) {
        if (c.sampler >= a.samplers.size() || c.target >= targets.size())
            throw std::out_of_range("animation '" + a.name + "': channel sampler " + count(c.sampler) +
                                    " of " + count(a.samplers.size()) + ", target " + count(c.target) +
                                    " of " + count(targets.size()));
        const AnimationSampler& s = a.samplers[c.sampler];
        const std::size_t need = c.path == AnimationPath::Rotation ? 4 : 3;
        if (c.path != AnimationPath::Weights && s.components != need)
            throw std::invalid_argument("animation '" + a.name + "': sampler " + count(c.sampler) + " has " +
                                        count(s.components) + " components, its path needs " + count(need));
        if (sampled_.size() < s.components) sampled_.resize(s.components);
        float* v = sampled_.data();
        s.sample(t, v, c.path == AnimationPath::Rotation);
        TargetMix& m = mix_[c.target];
        switch (c.path) {
        case AnimationPath::Translation:
            m.translation += w * glm::vec3(v[0], v[1], v[2]);
            m.translationWeight += w;
            break;
        case AnimationPath::Scale:
            m.scale += w * glm::vec3(v[0], v[1], v[2]);
            m.scaleWeight += w;
            break;
        case AnimationPath::Rotation: {
            glm::vec4 q(v[0], v[1], v[2], v[3]);
            if (m.rotationWeight == 0.0f) m.firstRotation = q;
            if (glm::dot(q, m.firstRotation) < 0.0f) q = -q; // one hemisphere, or the sum cancels
            m.rotation += w * q;
            m.rotationWeight += w;
            break;
        }
        case AnimationPath::Weights: {
            const std::vector<float>& rest = targets[c.target].weights;
            float* sum = weightSums_.data() + m.weightsOffset;
            for (std::size_t i = 0; i < m.weightsCount; ++i)
                sum[i] += w * (i < s.components ? v[i] : i < rest.size() ? rest[i] : 0.0f);
            m.weightsWeight += w;
            break;
        }
        }
    }
}

void AnimationPlayer::writePose() {
    for (std::size_t k = 0; k < targets.size(); ++k) {
        AnimationTarget& target = targets[k];
        const TargetMix& m = mix_[k];
        // (sum w_i v_i + max(0, 1 - W) rest) / max(W, 1): the rest pose fills a mix under weight 1.
        const auto mixed = [](auto sum, float w, auto rest) {
            return w == 0.0f ? rest : (sum + std::max(0.0f, 1.0f - w) * rest) / std::max(w, 1.0f);
        };
        const glm::vec3 translation = mixed(m.translation, m.translationWeight, target.translation);
        const glm::vec3 scale = mixed(m.scale, m.scaleWeight, target.scale);
        glm::quat rotation = target.rotation;
        if (m.rotationWeight > 0.0f) {
            glm::vec4 rest = toVec4(target.rotation);
            if (glm::dot(rest, m.firstRotation) < 0.0f) rest = -rest;
            const glm::vec4 q = m.rotation + std::max(0.0f, 1.0f - m.rotationWeight) * rest;
            const float len = glm::length(q);
            if (len > 1e-20f) rotation = glm::quat(q.w / len, q.x / len, q.y / len, q.z / len);
        }
        target.currentWeights.resize(m.weightsCount);
        for (std::size_t i = 0; i < m.weightsCount; ++i) {
            const float rest = i < target.weights.size() ? target.weights[i] : 0.0f;
            target.currentWeights[i] = mixed(weightSums_[m.weightsOffset + i], m.weightsWeight, rest);
        }
        if (m.weightsCount)
            for (const std::weak_ptr<Geometry>& g : target.morphs)
                if (const auto geometry = g.lock()) {
                    // A primitive with fewer targets than the mesh takes the first ones.
                    const std::size_t n =
                        std::min(target.currentWeights.size(), geometry->morphTargets.size());
                    geometry->setMorphWeights(std::span<const float>(target.currentWeights.data(), n));
                }
        if (const std::shared_ptr<Transform> t = target.transform.lock()) {
            const glm::mat4 matrix = glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) *
                                     glm::scale(glm::mat4(1.0f), scale);
            if (matrix != t->matrix()) t->setMatrix(matrix); // an unchanged pose leaves the bounds clean
        }
    }
}

// ---------------------------------------------------------------- AnimatedGroup
AnimatedGroup::AnimatedGroup()
    : player_(std::make_shared<AnimationPlayer>()) {
    // The player, not the node: a callback holding the node would keep it alive forever.
    updateCallback = [player = player_](Node&, UpdateVisitor& visitor) {
        player->update(visitor.simulationTime);
    };
}

AnimationPlayer* animationPlayer(Node& node) {
    auto* group = dynamic_cast<AnimatedGroup*>(&node);
    return group ? &group->player() : nullptr;
}

} // namespace sgfx
