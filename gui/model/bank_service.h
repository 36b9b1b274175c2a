// The studio's one filter bank service: Navigate and Auto Start ask it for the bank of the
// current frame; it builds each bank once on a worker (TaskRunner), hands the same immutable
// bank to every asker, and keeps the banks of the current frame until the frame changes.
// Requests of a bank being built join that build. No widgets here.
#pragma once

#include <QObject>
#include <QPointer>
#include <QString>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "glint/denoise/bank.h"
#include "glint/denoise/session_reapply.h"
#include "model/render_job.h"
#include "model/task_runner.h"

namespace glint::studio {

/// The options of the studio's banks (Navigate's and Auto Start's are one bank): `size` sampled
/// members over `region` (the whole frame when empty), built on the features as `session`
/// prefilters them. The filters and their fixed parameters (BankOptions::filterParams: an
/// external member's command, unet's weights) are those of `folder`, the options of the bank
/// folder a session names (Session::bankDir) — its filters when it names some, else
/// studioBankFilters() — so a bank made with `glint-denoise bank --filter-param` keeps them here.
denoise::BankOptions studioBankOptions(int size, const std::optional<Rect>& region,
                                       const denoise::SessionOptions& session,
                                       const denoise::BankOptions& folder = {});

class BankService : public QObject {
    Q_OBJECT
  public:
    using BankPtr = std::shared_ptr<const denoise::FilterBank>;
    /// Identifies one request (0: none).
    using Ticket = std::uint64_t;

    /// What an asker is told, always on the UI thread and never after withdraw(): the bank,
    /// the build's progress (members done / total), or why the build failed.
    struct Callbacks {
        std::function<void(BankPtr)> ready;
        std::function<void(double)> progress;
        std::function<void(const QString&)> failed;
    };

    /// Banks kept at once (the bank of Navigate's region and the whole frame's for Auto Start).
    static constexpr std::size_t kCacheSize = 2;

    explicit BankService(QObject* parent = nullptr);
    ~BankService() override;

    /// Asks for the bank of `frame` built with `options` (its size, seed, filters, their fixed
    /// parameters, prefilter and region matter; a region covering the whole frame is the whole
    /// frame; progress, cache folder and memory limit are the service's). `callbacks.ready` gets it
    /// after a queued call: from the cache, from the build of the same bank already running, or
    /// from a new build. Nothing is called once `context` is destroyed. Returns the ticket to
    /// withdraw the request with.
    Ticket request(FramePtr frame, const denoise::BankOptions& options, QObject* context,
                   Callbacks callbacks);
    /// Forgets a request (its callbacks are not called); a build nobody waits for is cancelled.
    void withdraw(Ticket ticket);
    /// The bank of `frame` and `options` if it is cached, else null.
    BankPtr cached(const FramePtr& frame, const denoise::BankOptions& options) const;

    /// The frame the banks are for: the banks of any other frame are dropped (a build of another
    /// frame still answers its askers, but is not kept). Null drops everything.
    void setFrame(FramePtr frame);
    FramePtr frame() const { return m_frame; }

    /// Builds started so far (tests count them).
    int builds() const { return m_builds; }
    /// True while a build runs.
    bool busy() const { return !m_building.empty(); }

  signals:
    void busyChanged(bool busy);

  private:
    // What makes two banks the same: the frame (the pointer: frames are immutable and shared)
    // and the options that change the members or their results.
    struct Key {
        FramePtr frame;
        int size = 0;
        std::uint64_t seed = 0;
        std::vector<std::string> filters;
        std::map<std::string, denoise::ParamValues> filterParams;
        bool prefilter = false;
        denoise::ParamValues prefilterParams;
        Rect region{};
        bool operator==(const Key& o) const;
    };
    struct Waiter {
        QPointer<QObject> context;
        Callbacks callbacks;
    };
    struct Build {
        Key key;
        denoise::BankOptions options;
        std::map<Ticket, Waiter> waiters;
    };

    static Key keyOf(const FramePtr& frame, const denoise::BankOptions& options);
    void start(std::uint64_t id);
    void finished(std::uint64_t id, BankPtr bank, const QString& error);
    void progressed(std::uint64_t id, double fraction);

    TaskRunner m_tasks;
    FramePtr m_frame;
    std::vector<std::pair<Key, BankPtr>> m_cache;   // most recently used first
    std::map<std::uint64_t, Build> m_building;      // by build id
    std::map<Ticket, std::uint64_t> m_ticketBuild;  // a waiting ticket's build
    std::uint64_t m_nextTicket = 1, m_nextBuild = 1;
    int m_builds = 0;
};

}  // namespace glint::studio
