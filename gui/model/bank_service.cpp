#include "model/bank_service.h"

#include <algorithm>
#include <atomic>

#include "model/learned_member.h"

namespace glint::studio {

denoise::BankOptions studioBankOptions(int size, const std::optional<Rect>& region,
                                       const denoise::SessionOptions& session,
                                       const denoise::BankOptions& folder) {
    denoise::BankOptions options;
    options.size = size;
    // The folder's filters, else the studio's (the learned filter too, when it runs here).
    options.filters = folder.filters.empty() ? studioBankFilters() : folder.filters;
    options.filterParams = folder.filterParams;
    options.region = region;
    // The bank reads the features as the session's filters do.
    options.prefilter = session.prefilter;
    options.prefilterParams = session.prefilterParams;
    return options;
}

bool BankService::Key::operator==(const Key& o) const {
    return frame == o.frame && size == o.size && seed == o.seed && filters == o.filters &&
           filterParams == o.filterParams && prefilter == o.prefilter &&
           (!prefilter || prefilterParams == o.prefilterParams) && region == o.region;
}

BankService::BankService(QObject* parent) : QObject(parent) {}

// The runner's destructor cancels the builds and waits for them; their askers hear nothing.
BankService::~BankService() = default;

BankService::Key BankService::keyOf(const FramePtr& frame, const denoise::BankOptions& options) {
    Key key;
    key.frame = frame;
    key.size = options.size;
    key.seed = options.seed;
    key.filters = options.filters;
    std::sort(key.filters.begin(), key.filters.end());
    key.filterParams = options.filterParams;
    key.prefilter = options.prefilter;
    key.prefilterParams = options.prefilterParams;
    // The bank's own rule: no region is the whole frame.
    const Rect whole{0, frame->width(), 0, frame->height()};
    key.region = options.region.value_or(whole);
    return key;
}

BankService::Ticket BankService::request(FramePtr frame, const denoise::BankOptions& options,
                                         QObject* context, Callbacks callbacks) {
    if (!frame) return 0;
    const Key key = keyOf(frame, options);
    const Ticket ticket = m_nextTicket++;
    // 1. Cached: answer from the cache (queued, as a build would).
    for (auto it = m_cache.begin(); it != m_cache.end(); ++it) {
        if (!(it->first == key)) continue;
        std::rotate(m_cache.begin(), it, it + 1);  // most recently used first
        BankPtr bank = m_cache.front().second;
        m_ticketBuild[ticket] = 0;
        QMetaObject::invokeMethod(
            this,
            [this, ticket, bank, guard = QPointer<QObject>(context),
             ready = std::move(callbacks.ready)] {
                if (m_ticketBuild.erase(ticket) && guard && ready) ready(bank);
            },
            Qt::QueuedConnection);
        return ticket;
    }
    // 2. Being built: wait for that build.
    for (auto& [id, build] : m_building) {
        if (!(build.key == key)) continue;
        build.waiters[ticket] = {context, std::move(callbacks)};
        m_ticketBuild[ticket] = id;
        return ticket;
    }
    // 3. A new build.
    const std::uint64_t id = m_nextBuild++;
    Build& build = m_building[id];
    build.key = key;
    build.options = options;
    build.options.region = key.region;
    build.options.progress = {};
    build.options.cacheDir.clear();
    build.waiters[ticket] = {context, std::move(callbacks)};
    m_ticketBuild[ticket] = id;
    start(id);
    return ticket;
}

void BankService::start(std::uint64_t id) {
    const Build& build = m_building.at(id);
    FramePtr frame = build.key.frame;
    denoise::BankOptions options = build.options;
    ++m_builds;
    if (m_building.size() == 1) emit busyChanged(true);
    m_tasks.run<BankPtr>(
        QStringLiteral("bank-%1").arg(id),
        [this, id, frame, options](const TaskRunner::CancelFlag& cancel) mutable {
            // Called on the worker: progress is posted to the UI thread at most every 1 %.
            auto last = std::make_shared<std::atomic<int>>(-1);
            options.progress = [this, id, cancel, last](double fraction) {
                const int percent = int(fraction * 100.0);
                if (percent != last->exchange(percent))
                    QMetaObject::invokeMethod(
                        &m_tasks, [this, id, fraction] { progressed(id, fraction); },
                        Qt::QueuedConnection);
                return !cancel->load();
            };
            return BankPtr(
                std::make_shared<const denoise::FilterBank>(denoise::buildBank(*frame, options)));
        },
        [this, id](BankPtr bank) { finished(id, std::move(bank), QString()); },
        [this, id](const QString& message) { finished(id, nullptr, message); });
}

void BankService::progressed(std::uint64_t id, double fraction) {
    auto it = m_building.find(id);
    if (it == m_building.end()) return;
    // A copy: a callback may withdraw or request.
    const std::map<Ticket, Waiter> waiters = it->second.waiters;
    for (const auto& [ticket, waiter] : waiters)
        if (m_ticketBuild.count(ticket) && waiter.context && waiter.callbacks.progress)
            waiter.callbacks.progress(fraction);
}

void BankService::finished(std::uint64_t id, BankPtr bank, const QString& error) {
    auto it = m_building.find(id);
    if (it == m_building.end()) return;
    Build build = std::move(it->second);
    m_building.erase(it);
    if (m_building.empty()) emit busyChanged(false);
    // Kept only when it is of the current frame.
    if (bank && build.key.frame == m_frame) {
        m_cache.insert(m_cache.begin(), {build.key, bank});
        if (m_cache.size() > kCacheSize) m_cache.resize(kCacheSize);
    }
    for (const auto& [ticket, waiter] : build.waiters) {
        if (!m_ticketBuild.erase(ticket) || !waiter.context) continue;  // withdrawn, or gone
        const Callbacks& callbacks = waiter.callbacks;
        if (bank && callbacks.ready) callbacks.ready(bank);
        if (!bank && callbacks.failed) callbacks.failed(error);
    }
}

void BankService::withdraw(Ticket ticket) {
    auto t = m_ticketBuild.find(ticket);
    if (t == m_ticketBuild.end()) return;
    const std::uint64_t id = t->second;
    m_ticketBuild.erase(t);
    auto it = m_building.find(id);
    if (it == m_building.end()) return;
    it->second.waiters.erase(ticket);
    if (!it->second.waiters.empty()) return;
    // Nobody waits: stop the build (the runner drops its result).
    m_tasks.cancel(QStringLiteral("bank-%1").arg(id));
    m_building.erase(it);
    if (m_building.empty()) emit busyChanged(false);
}

BankService::BankPtr BankService::cached(const FramePtr& frame,
                                         const denoise::BankOptions& options) const {
    if (!frame) return nullptr;
    const Key key = keyOf(frame, options);
    for (const auto& [k, bank] : m_cache)
        if (k == key) return bank;
    return nullptr;
}

void BankService::setFrame(FramePtr frame) {
    if (frame == m_frame) return;
    m_frame = std::move(frame);
    std::erase_if(m_cache, [this](const auto& entry) { return entry.first.frame != m_frame; });
}

}  // namespace glint::studio
