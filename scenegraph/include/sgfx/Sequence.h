#pragma once
#include "sgfx/Export.h"
#include "sgfx/Group.h"

#include <cstdint>
#include <vector>

namespace sgfx {

/// Shows one child at a time, each for its own time, like OSG's osg::Sequence: a flip-book
/// driven by the UpdateVisitor's simulation time. Visitors in ActiveChildren mode (cull, update,
/// intersection) visit only the shown child; AllChildren visitors and the bound see all of them
/// (so the bound does not change as frames flip).
///
/// The frames played are begin..end (end may be before begin: played backwards). LOOP plays
/// begin..end again and again; SWING plays begin..end, then back end-1..begin+1, and so on. One
/// repeat is one such cycle; after `repeats` cycles (-1: forever) the sequence stops on its last
/// frame (end for LOOP, begin for SWING, where a swing comes home). Like OSG, a new sequence is
/// stopped and shows nothing until setMode(Mode::Start).
class SGFX_API Sequence : public Group {
public:
    enum class LoopMode : std::uint8_t { Loop, Swing };
    /// Start (re)starts from begin at the next update; Stop freezes the shown frame; Pause
    /// freezes a running sequence and Resume continues it (the paused time is skipped).
    enum class Mode : std::uint8_t { Start, Stop, Pause, Resume };

    static std::shared_ptr<Sequence> create() { return std::make_shared<Sequence>(); }
    void accept(NodeVisitor& v) override;
    void traverse(NodeVisitor& v) override;

    /// As Group::addChild, shown for `seconds` (others get defaultTime()).
    using Group::addChild;
    void addChild(NodePtr child, double seconds);

    /// Every setter throws std::invalid_argument naming the sequence and keeps the old state for
    /// a non-finite or negative time, an index that is not a child, or a bad enum value.
    void setTime(std::size_t frame, double seconds);
    double time(std::size_t frame) const;
    /// The time of children added without one (OSG's default: 1 s).
    void setDefaultTime(double seconds);
    double defaultTime() const { return defaultTime_; }
    /// begin and end are child indices, or -1 for the last child (resolved when playing).
    void setInterval(LoopMode loopMode, int begin, int end);
    LoopMode loopMode() const { return loopMode_; }
    int begin() const { return begin_; }
    int end() const { return end_; }
    /// speed: finite and > 0 (2 plays twice as fast); repeats: cycles to play, -1 for ever.
    void setDuration(double speed, int repeats = -1);
    double speed() const { return speed_; }
    int repeats() const { return repeats_; }
    void setMode(Mode mode);
    /// Start, Stop or Pause (Resume turns a paused sequence back to Start).
    Mode mode() const { return mode_; }

    /// The child shown, or -1 for none.
    int value() const { return value_; }
    /// Seconds played since Start, speed applied, pauses left out.
    double elapsed() const { return elapsed_; }
    /// Advances the clock to `simulationTime` and picks the shown child (the UpdateVisitor calls
    /// it; a sequence under several parents advances once per time).
    void advanceTo(double simulationTime);
    /// The child shown `elapsed` seconds after Start, and whether the repeats are used up then.
    int frameAt(double elapsed, bool* finished = nullptr) const;

protected:
    void childInserted(std::size_t index) override;
    void childRemoved(std::size_t index) override;

private:
    void refuse(const std::string& why) const;
    void checkSeconds(double seconds, const char* what) const;
    /// The children one cycle shows, in order.
    std::vector<std::size_t> cycle() const;
    std::vector<double> times_;
    double defaultTime_ = 1.0;
    LoopMode loopMode_ = LoopMode::Loop;
    int begin_ = 0;
    int end_ = -1;
    double speed_ = 1.0;
    int repeats_ = -1;
    Mode mode_ = Mode::Stop;
    int value_ = -1;
    double elapsed_ = 0.0;
    double lastTime_ = 0.0;
    bool haveLastTime_ = false; ///< false after Start and Resume: the next update sets the clock
};

} // namespace sgfx
