#pragma once
// sgfx-view's animation controls, free of GLFW and ImGui so the tests can drive them: --time and
// --animation's choice of an animation and a pose, and the window panel's timeline (choice,
// play/pause, scrub, speed, loop/clamp) as calls on the scene's AnimationPlayers.
#include <sgfx/Animation.h>
#include <sgfx/Node.h>

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace view {

// Every AnimatedGroup's player under `root`, depth first (a scene may hold several models).
std::vector<sgfx::AnimationPlayer*> findPlayers(sgfx::Node& root);

// One line per animation: "  [model M] INDEX  NAME  DURATION s, N channels" (the model number
// only when there are several players).
std::string listAnimations(const std::vector<sgfx::AnimationPlayer*>& players);

// A bad --time or --animation for the loaded files; the message lists their animations.
struct AnimationChoiceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// --animation NAME|INDEX and --time SECONDS on the loaded players: an integer is an index, anything
// else a name; each player that has the animation plays it (the others their current one), then,
// with a time, seeks it and pauses so that every later frame shows that pose. Returns what was
// chosen ("animation 0 'Take' at 0.5 s of 3.708 s"); empty when neither option was given. Throws
// AnimationChoiceError when no player has the animation, or when a time or an animation is asked
// of files without animations.
std::string chooseAnimation(const std::vector<sgfx::AnimationPlayer*>& players,
                            const std::optional<std::string>& animation, std::optional<double> time);

// The panel's timeline. Its entries are every player's animations; the selected entry's player is
// the one the controls drive (the others keep playing as they are).
class AnimationControls {
public:
    struct Entry {
        sgfx::AnimationPlayer* player = nullptr;
        std::size_t index = 0; // into player->animations
        std::string label;     // the name, or "animation N"; "[model M]" added with several players
        double duration = 0.0;
    };

    // Finds the players under `root` (again after a new model was loaded) and selects the first
    // player's current animation.
    void attach(sgfx::Node& root);
    const std::vector<Entry>& entries() const { return entries_; }
    bool empty() const { return entries_.empty(); }
    int selected() const { return selected_; }
    // Plays entry `e` from its start on its player, paused if the player was paused.
    void select(std::size_t e);
    void next(); // the following entry, wrapping around (a key cycles through them)

    bool playing() const;
    void togglePlay();
    // Dragging the time slider: begin pauses (remembering whether it played), scrub seeks, end
    // resumes when it played before.
    void beginScrub();
    void scrub(double seconds);
    void endScrub();
    bool scrubbing() const { return scrubbing_; }

    double speed() const;
    void setSpeed(double speed);
    bool loop() const;
    void setLoop(bool loop);
    double time() const;     // of the selected animation, at the last update
    double duration() const; // of the selected animation

private:
    std::vector<Entry> entries_;
    int selected_ = -1;
    bool scrubbing_ = false, playedBeforeScrub_ = false;
    const Entry* current() const { return selected_ < 0 ? nullptr : &entries_[std::size_t(selected_)]; }
};

} // namespace view
