// Switch (children on or off) and Sequence (one child at a time, by the update clock).
#include "sgfx/Switch.h"
#include "sgfx/Sequence.h"

#include "sgfx/NodeVisitor.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {
std::string label(const Node& n) {
    return n.name.empty() ? std::string("<unnamed>") : "'" + n.name + "'";
}
} // namespace

// ---------------------------------------------------------------- Switch
void Switch::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Switch::traverse(NodeVisitor& v) {
    if (v.mode != NodeVisitor::Mode::ActiveChildren) {
        Group::traverse(v);
        return;
    }
    for (std::size_t i = 0; i < numChildren(); ++i)
        if (values_[i] && v.accepts(*child(i))) child(i)->accept(v);
}

void Switch::addChild(NodePtr child, bool on) {
    const std::size_t index = numChildren();
    Group::addChild(std::move(child));
    values_[index] = on;
    dirtyBound();
}

void Switch::checkIndex(std::size_t index, const char* what) const {
    if (index >= values_.size())
        throw std::out_of_range(std::string("sgfx: Switch ") + label(*this) + "::" + what + ": no child " +
                                std::to_string(index) + " (" + std::to_string(values_.size()) + " children)");
}

void Switch::setValue(std::size_t index, bool on) {
    checkIndex(index, "setValue");
    if (values_[index] == on) return;
    values_[index] = on;
    dirtyBound(); // the bound covers the children that are on
}

bool Switch::value(std::size_t index) const {
    checkIndex(index, "value");
    return values_[index];
}

void Switch::setAll(bool on) {
    values_.assign(values_.size(), on);
    dirtyBound();
}

void Switch::setSingleChildOn(std::size_t index) {
    checkIndex(index, "setSingleChildOn");
    values_.assign(values_.size(), false);
    values_[index] = true;
    dirtyBound();
}

BoundingSphere Switch::computeBound() const {
    // Group's bound over the children that are on (OSG's Switch::computeBound).
    BoundingSphere out;
    for (std::size_t i = 0; i < numChildren(); ++i)
        if (values_[i]) out.expandBy(child(i)->bound());
    return out;
}

void Switch::childInserted(std::size_t index) {
    values_.insert(values_.begin() + std::ptrdiff_t(index), newChildDefault_);
}

void Switch::childRemoved(std::size_t index) {
    values_.erase(values_.begin() + std::ptrdiff_t(index));
}

// ---------------------------------------------------------------- Sequence
void Sequence::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Sequence::traverse(NodeVisitor& v) {
    if (v.mode != NodeVisitor::Mode::ActiveChildren) {
        Group::traverse(v);
        return;
    }
    if (value_ >= 0 && std::size_t(value_) < numChildren() && v.accepts(*child(std::size_t(value_))))
        child(std::size_t(value_))->accept(v);
}

void Sequence::refuse(const std::string& why) const {
    throw std::invalid_argument("sgfx: Sequence " + label(*this) + ": " + why);
}

void Sequence::checkSeconds(double seconds, const char* what) const {
    if (!std::isfinite(seconds) || seconds < 0.0)
        refuse(std::string(what) + " " + std::to_string(seconds) + " s must be finite and >= 0");
}

void Sequence::addChild(NodePtr child, double seconds) {
    checkSeconds(seconds, "time");
    const std::size_t index = numChildren();
    Group::addChild(std::move(child));
    times_[index] = seconds;
}

void Sequence::setTime(std::size_t frame, double seconds) {
    if (frame >= times_.size())
        refuse("setTime: no child " + std::to_string(frame) + " (" + std::to_string(times_.size()) +
               " children)");
    checkSeconds(seconds, "time");
    times_[frame] = seconds;
}

double Sequence::time(std::size_t frame) const {
    if (frame >= times_.size()) refuse("time: no child " + std::to_string(frame));
    return times_[frame];
}

void Sequence::setDefaultTime(double seconds) {
    checkSeconds(seconds, "default time");
    defaultTime_ = seconds;
}

void Sequence::setInterval(LoopMode loopMode, int begin, int end) {
    if (loopMode != LoopMode::Loop && loopMode != LoopMode::Swing)
        refuse("loop mode " + std::to_string(int(loopMode)) + " is not a Sequence::LoopMode");
    const int n = int(numChildren());
    for (int i : {begin, end})
        if (i < -1 || i >= n)
            refuse("interval [" + std::to_string(begin) + ", " + std::to_string(end) +
                   "]: indices must be children (0.." + std::to_string(n - 1) + ") or -1 for the last");
    loopMode_ = loopMode;
    begin_ = begin;
    end_ = end;
}

void Sequence::setDuration(double speed, int repeats) {
    if (!std::isfinite(speed) || !(speed > 0.0))
        refuse("speed " + std::to_string(speed) + " must be finite and > 0");
    if (repeats < -1) refuse("repeats " + std::to_string(repeats) + " must be >= 0, or -1 for ever");
    speed_ = speed;
    repeats_ = repeats;
}

void Sequence::setMode(Mode mode) {
    switch (mode) {
    case Mode::Start:
        mode_ = Mode::Start;
        elapsed_ = 0.0;
        haveLastTime_ = false;
        value_ = frameAt(0.0);
        return;
    case Mode::Stop:
        mode_ = Mode::Stop;
        return;
    case Mode::Pause:
        if (mode_ == Mode::Start) mode_ = Mode::Pause;
        return;
    case Mode::Resume:
        if (mode_ != Mode::Pause) return;
        mode_ = Mode::Start;
        haveLastTime_ = false; // the paused time is skipped
        return;
    }
    refuse("mode " + std::to_string(int(mode)) + " is not a Sequence::Mode");
}

std::vector<std::size_t> Sequence::cycle() const {
    const int n = int(numChildren());
    if (n == 0) return {};
    auto resolve = [n](int i) { return i < 0 || i >= n ? n - 1 : i; }; // -1, or a child since removed
    const int b = resolve(begin_), e = resolve(end_);
    const int step = e >= b ? 1 : -1;
    std::vector<std::size_t> out;
    for (int i = b;; i += step) {
        out.push_back(std::size_t(i));
        if (i == e) break;
    }
    if (loopMode_ == LoopMode::Swing)
        for (int i = e - step; i != b && b != e; i -= step)
            out.push_back(std::size_t(i));
    return out;
}

int Sequence::frameAt(double elapsed, bool* finished) const {
    if (finished) *finished = false;
    const std::vector<std::size_t> frames = cycle();
    if (frames.empty()) return -1;
    double length = 0.0;
    for (std::size_t f : frames)
        length += times_[f];
    const int last = int(loopMode_ == LoopMode::Swing ? frames.front() : frames.back());
    if (repeats_ >= 0 && elapsed >= double(repeats_) * length) {
        if (finished) *finished = true;
        return last;
    }
    if (!(length > 0.0)) return last; // every frame takes no time
    double t = std::fmod(elapsed, length);
    for (std::size_t f : frames) {
        if (t < times_[f]) return int(f);
        t -= times_[f];
    }
    return last; // rounding at the cycle's end
}

void Sequence::advanceTo(double simulationTime) {
    if (mode_ != Mode::Start) return;
    if (haveLastTime_) elapsed_ += std::max(0.0, simulationTime - lastTime_) * speed_;
    lastTime_ = simulationTime;
    haveLastTime_ = true;
    bool finished = false;
    value_ = frameAt(elapsed_, &finished);
    if (finished) mode_ = Mode::Stop;
}

void Sequence::childInserted(std::size_t index) {
    times_.insert(times_.begin() + std::ptrdiff_t(index), defaultTime_);
}

void Sequence::childRemoved(std::size_t index) {
    times_.erase(times_.begin() + std::ptrdiff_t(index));
    if (value_ >= int(times_.size())) value_ = int(times_.size()) - 1;
}

} // namespace sgfx
