#include "AnimationControls.h"

#include <sgfx/FindNode.h>

#include <charconv>
#include <cstdio>

namespace view {

std::vector<sgfx::AnimationPlayer*> findPlayers(sgfx::Node& root) {
    std::vector<sgfx::AnimationPlayer*> players;
    for (const sgfx::NodePtr& n :
         sgfx::findNodesIf(root, [](sgfx::Node& m) { return sgfx::animationPlayer(m); }))
        players.push_back(sgfx::animationPlayer(*n));
    return players;
}

namespace {

std::string animationLabel(const sgfx::AnimationPlayer& p, std::size_t i) {
    const std::string& name = p.animations[i].name;
    return name.empty() ? "animation " + std::to_string(i) : name;
}

// An integer names an index; `out` is set only when the whole text is one.
bool parseIndex(const std::string& text, long long& out) {
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, out);
    return !text.empty() && r.ec == std::errc() && r.ptr == end;
}

} // namespace

std::string listAnimations(const std::vector<sgfx::AnimationPlayer*>& players) {
    std::string out;
    char line[512];
    for (std::size_t m = 0; m < players.size(); ++m) {
        const sgfx::AnimationPlayer& p = *players[m];
        for (std::size_t i = 0; i < p.animations.size(); ++i) {
            const std::string model = players.size() > 1 ? "[model " + std::to_string(m) + "] " : "";
            std::snprintf(line, sizeof line, "  %s%zu  '%s'  %.3f s, %zu channels\n", model.c_str(), i,
                          p.animations[i].name.c_str(), double(p.animations[i].duration()),
                          p.animations[i].channels.size());
            out += line;
        }
    }
    return out.empty() ? "  (no animations)\n" : out;
}

std::string chooseAnimation(const std::vector<sgfx::AnimationPlayer*>& players,
                            const std::optional<std::string>& animation, std::optional<double> time) {
    if (!animation && !time) return {};
    if (players.empty())
        throw AnimationChoiceError(std::string(animation ? "--animation" : "--time") +
                                   ": the files have no animations");
    // Each player's index for the option, or -1 where it has no such animation.
    std::vector<long long> chosen(players.size(), -1);
    bool found = !animation;
    for (std::size_t m = 0; m < players.size(); ++m) {
        const sgfx::AnimationPlayer& p = *players[m];
        long long i = -1;
        if (!animation)
            i = p.current() >= 0 ? p.current() : 0;
        else if (!parseIndex(*animation, i))
            i = p.find(*animation);
        if (i >= 0 && std::size_t(i) < p.animations.size()) {
            chosen[m] = i;
            found = true;
        }
    }
    if (!found)
        throw AnimationChoiceError("--animation: no animation '" + *animation +
                                   "' in the files (an integer is an index); they have:\n" +
                                   listAnimations(players));
    std::string what;
    for (std::size_t m = 0; m < players.size(); ++m) {
        sgfx::AnimationPlayer& p = *players[m];
        const long long i = chosen[m] >= 0 ? chosen[m] : (p.current() >= 0 ? p.current() : 0);
        if (p.animations.empty()) continue;
        p.play(std::size_t(i));
        if (time) {
            p.seek(*time);
            p.pause(); // every later frame (TAA, particles settling) keeps this pose
        }
        if (!what.empty() || chosen[m] < 0) continue;
        char line[512];
        const double at = time ? p.time(std::size_t(i)) : 0.0;
        std::snprintf(line, sizeof line, "animation %lld '%s' (%.3f s)", i,
                      p.animations[std::size_t(i)].name.c_str(),
                      double(p.animations[std::size_t(i)].duration()));
        what = line;
        if (time) {
            std::snprintf(line, sizeof line, " at %g s", *time);
            what += line;
            if (at != *time) { // looped past the end
                std::snprintf(line, sizeof line, " (%g s into the loop)", at);
                what += line;
            }
        }
    }
    return what;
}

void AnimationControls::attach(sgfx::Node& root) {
    entries_.clear();
    selected_ = -1;
    scrubbing_ = false;
    const std::vector<sgfx::AnimationPlayer*> players = findPlayers(root);
    for (std::size_t m = 0; m < players.size(); ++m) {
        sgfx::AnimationPlayer& p = *players[m];
        for (std::size_t i = 0; i < p.animations.size(); ++i) {
            Entry e{&p, i, animationLabel(p, i), double(p.animations[i].duration())};
            if (players.size() > 1) e.label += " [model " + std::to_string(m) + "]";
            if (selected_ < 0 && p.current() == int(i)) selected_ = int(entries_.size());
            entries_.push_back(std::move(e));
        }
    }
    if (selected_ < 0 && !entries_.empty()) selected_ = 0;
}

void AnimationControls::select(std::size_t e) {
    if (e >= entries_.size()) return;
    const Entry& to = entries_[e];
    const bool wasPlaying = to.player->playing();
    to.player->play(to.index);
    if (!wasPlaying) to.player->pause();
    selected_ = int(e);
}

void AnimationControls::next() {
    if (!entries_.empty()) select((std::size_t(selected_ + 1)) % entries_.size());
}

bool AnimationControls::playing() const {
    return current() && current()->player->playing();
}

void AnimationControls::togglePlay() {
    const Entry* e = current();
    if (!e) return;
    if (e->player->current() < 0) // never played: start it
        e->player->play(e->index);
    else if (e->player->playing())
        e->player->pause();
    else
        e->player->resume();
}

void AnimationControls::beginScrub() {
    const Entry* e = current();
    if (!e || scrubbing_) return;
    scrubbing_ = true;
    playedBeforeScrub_ = e->player->playing();
    e->player->pause();
}

void AnimationControls::scrub(double seconds) {
    const Entry* e = current();
    if (!e) return;
    if (!scrubbing_) beginScrub();
    if (e->player->current() != int(e->index)) { // another caller switched it: take it back
        e->player->play(e->index);
        e->player->pause();
    }
    e->player->seek(seconds);
}

void AnimationControls::endScrub() {
    const Entry* e = current();
    if (!e || !scrubbing_) return;
    scrubbing_ = false;
    if (playedBeforeScrub_) e->player->resume();
}

double AnimationControls::speed() const {
    return current() ? current()->player->speed() : 1.0;
}

void AnimationControls::setSpeed(double speed) {
    if (current()) current()->player->setSpeed(speed);
}

bool AnimationControls::loop() const {
    return !current() || current()->player->wrap() == sgfx::AnimationPlayer::Wrap::Loop;
}

void AnimationControls::setLoop(bool loop) {
    const Entry* e = current();
    if (!e) return;
    // The clock runs on from its anchor: re-anchor at the present (wrapped) time first, or Clamp
    // would jump to the end after a few loops.
    if (e->player->current() == int(e->index)) e->player->seek(e->player->time(e->index));
    e->player->setWrap(loop ? sgfx::AnimationPlayer::Wrap::Loop : sgfx::AnimationPlayer::Wrap::Clamp);
}

double AnimationControls::time() const {
    const Entry* e = current();
    return e ? e->player->time(e->index) : 0.0;
}

double AnimationControls::duration() const {
    return current() ? current()->duration : 0.0;
}

} // namespace view
