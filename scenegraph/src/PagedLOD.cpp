// PagedLOD (slots loaded on demand) and DatabasePager (the loading thread and the between-frames
// attach and expiry).
#include "sgfx/DatabasePager.h"

#include "sgfx/NodeVisitor.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {
std::string label(const Node& n) {
    return n.name.empty() ? std::string("<unnamed>") : "'" + n.name + "'";
}

/// What an unloaded slot holds: no bound, no children, so every visitor passes over it.
class NotLoaded final : public Node {};

bool isPlaceholder(const NodePtr& n) {
    return dynamic_cast<const NotLoaded*>(n.get()) != nullptr;
}
} // namespace

// ---------------------------------------------------------------- PagedLOD
void PagedLOD::accept(NodeVisitor& v) {
    v.apply(*this);
}

std::uint64_t PagedLOD::nextId() {
    static std::atomic<std::uint64_t> next{1};
    return next++;
}

void PagedLOD::addChild(const std::filesystem::path& file, float min, float max) {
    if (file.empty())
        throw std::invalid_argument("sgfx: PagedLOD " + label(*this) + " child " +
                                    std::to_string(numChildren()) + ": empty file name");
    const std::size_t index = numChildren();
    LOD::addChild(std::make_shared<NotLoaded>(), min, max); // checks the range first
    slots_[index].file = file;
}

void PagedLOD::setFileName(std::size_t index, const std::filesystem::path& file) {
    if (index >= slots_.size())
        throw std::out_of_range("sgfx: PagedLOD " + label(*this) + " has no child " + std::to_string(index));
    Slot& s = slots_[index];
    s.file = file;
    s.state = State::Idle;
    s.id = nextId(); // a load in flight for the old name no longer matches
}

const std::filesystem::path& PagedLOD::fileName(std::size_t index) const {
    return slots_.at(index).file;
}

std::filesystem::path PagedLOD::resolvedFileName(std::size_t index) const {
    const std::filesystem::path& f = slots_.at(index).file;
    return f.is_relative() && !databasePath_.empty() ? databasePath_ / f : f;
}

bool PagedLOD::loaded(std::size_t index) const {
    return !isPlaceholder(child(index));
}

bool PagedLOD::failed(std::size_t index) const {
    return slots_.at(index).state == State::Failed;
}

std::size_t PagedLOD::coarserLoaded(std::size_t index) const {
    const float fine = fineness(index);
    std::size_t best = npos;
    for (std::size_t j = 0; j < numChildren(); ++j) {
        if (j == index || !loaded(j)) continue;
        const float f = fineness(j);
        if (f < fine && (best == npos || f > fineness(best))) best = j;
    }
    return best;
}

void PagedLOD::markUsed(std::size_t index, std::uint64_t frame, double time) {
    Slot& s = slots_.at(index);
    s.lastUsedFrame = frame;
    s.lastUsedTime = time;
}

std::size_t PagedLOD::slotIndex(std::uint64_t id) const {
    for (std::size_t i = 0; i < slots_.size(); ++i)
        if (slots_[i].id == id) return i;
    return npos;
}

BoundingSphere PagedLOD::computeBound() const {
    BoundingSphere b = LOD::computeBound();
    if (const auto& user = userSphere()) {
        if (!b.valid()) return *user;
        b.expandBy(*user);
    }
    return b;
}

void PagedLOD::childInserted(std::size_t index) {
    LOD::childInserted(index);
    Slot s;
    s.id = nextId();
    slots_.insert(slots_.begin() + std::ptrdiff_t(index), std::move(s));
}

void PagedLOD::childRemoved(std::size_t index) {
    LOD::childRemoved(index);
    slots_.erase(slots_.begin() + std::ptrdiff_t(index));
}

// ---------------------------------------------------------------- DatabasePager
DatabasePager::~DatabasePager() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        queue_.clear();
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
}

void DatabasePager::setLoader(Loader loader) {
    std::lock_guard lock(mutex_);
    loader_ = std::move(loader);
}

void DatabasePager::setExpiry(std::uint64_t frames, double seconds) {
    if (!std::isfinite(seconds) || seconds < 0.0)
        throw std::invalid_argument("sgfx: DatabasePager::setExpiry: " + std::to_string(seconds) +
                                    " s must be finite and >= 0");
    expiryFrames_ = frames;
    expiryDelay_ = seconds;
}

DatabasePager::Stats DatabasePager::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

std::vector<std::string> DatabasePager::errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
}

void DatabasePager::request(PagedLOD& node, std::size_t index) {
    PagedLOD::Slot& s = node.slots_.at(index);
    if (s.state != PagedLOD::State::Idle || s.file.empty() || node.loaded(index)) return;
    s.state = PagedLOD::State::Requested;
    Request r{node.weak_from_this(), s.id, node.resolvedFileName(index), label(node), node.loader()};
    {
        std::lock_guard lock(mutex_);
        if (stop_) return;
        queue_.push_back(std::move(r));
        ++stats_.requested;
        ++stats_.pending;
        if (!worker_.joinable()) worker_ = std::thread([this] { run(); });
    }
    wake_.notify_one();
}

void DatabasePager::markUsed(PagedLOD& node, std::size_t index) {
    node.markUsed(index, frameNumber_, time_);
    // A child present from the start that has a file may be unloaded too: track its node.
    if (!node.registered_ && !node.slots_[index].file.empty()) {
        node.registered_ = true;
        tracked_.push_back(node.weak_from_this());
    }
}

// The worker: one load at a time, outside the lock, so a slow file never holds up a frame.
void DatabasePager::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        Result result{std::move(queue_.front()), nullptr, {}};
        queue_.pop_front();
        if (result.request.node.expired()) { // its node is gone: nothing to load for
            --stats_.pending;
            if (queue_.empty()) idle_.notify_all();
            continue;
        }
        Loader loader = result.request.loader ? result.request.loader : loader_;
        loading_ = true;
        lock.unlock();
        try {
            if (!loader) throw std::runtime_error("no loader set on the node or the pager");
            result.node = loader(result.request.file);
            if (!result.node) throw std::runtime_error("the loader returned no node");
        } catch (const std::exception& e) {
            result.node.reset();
            result.error = e.what();
        }
        lock.lock();
        loading_ = false;
        ready_.push_back(std::move(result));
        if (queue_.empty()) idle_.notify_all();
    }
}

bool DatabasePager::waitUntilIdle(std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    return idle_.wait_for(lock, timeout, [&] { return queue_.empty() && !loading_; });
}

void DatabasePager::attach(Result& r) {
    auto node = std::static_pointer_cast<PagedLOD>(r.request.node.lock());
    const std::size_t index = node ? node->slotIndex(r.request.slotId) : PagedLOD::npos;
    if (index == PagedLOD::npos) return; // the node or its slot changed meanwhile
    PagedLOD::Slot& s = node->slots_[index];
    if (!r.error.empty()) {
        s.state = PagedLOD::State::Failed; // reported once: never asked for again
        const std::string line = "sgfx: PagedLOD " + r.request.nodeName + " could not load '" +
                                 r.request.file.string() + "': " + r.error;
        std::fprintf(stderr, "%s\n", line.c_str());
        std::lock_guard lock(mutex_);
        errors_.push_back(line);
        ++stats_.failed;
        return;
    }
    node->replaceChild(index, std::move(r.node));
    s.state = PagedLOD::State::Idle;
    node->markUsed(index, frameNumber_, time_); // its expiry counts from now
    if (!node->registered_) {
        node->registered_ = true;
        tracked_.push_back(node);
    }
    std::lock_guard lock(mutex_);
    ++stats_.loaded;
}

// Unloads the slots with a file that no cull drew for the expiry frames and time.
void DatabasePager::expire(std::vector<NodePtr>& unloaded) {
    std::size_t live = 0, expired = 0;
    std::erase_if(tracked_, [](const std::weak_ptr<Node>& w) { return w.expired(); });
    for (const auto& w : tracked_) {
        auto node = std::static_pointer_cast<PagedLOD>(w.lock());
        for (std::size_t i = 0; i < node->numChildren(); ++i) {
            PagedLOD::Slot& s = node->slots_[i];
            if (s.file.empty() || !node->loaded(i)) continue;
            const bool unused =
                frameNumber_ - s.lastUsedFrame > expiryFrames_ && time_ - s.lastUsedTime >= expiryDelay_;
            if (!unused) {
                ++live;
                continue;
            }
            unloaded.push_back(node->child(i));
            node->replaceChild(i, std::make_shared<NotLoaded>());
            s.id = PagedLOD::nextId();
            s.state = PagedLOD::State::Idle;
            ++expired;
        }
    }
    std::lock_guard lock(mutex_);
    stats_.expired += expired;
    stats_.live = live;
}

std::vector<NodePtr> DatabasePager::updateSceneGraph(std::uint64_t frameNumber, double time) {
    frameNumber_ = frameNumber;
    time_ = time;
    std::vector<Result> ready;
    {
        std::lock_guard lock(mutex_);
        ready.swap(ready_);
        stats_.pending -= ready.size();
    }
    for (Result& r : ready)
        attach(r);
    std::vector<NodePtr> unloaded;
    expire(unloaded);
    return unloaded;
}

} // namespace sgfx
