// Sending frames to a running tev (docs/renderer.md, "Watching a render in tev"): a connection
// that fails once, with one warning, and never stops the caller; and a display that creates
// the image once with every layer as tev channels, then sends each frame shown as tiles, on a
// thread of its own so that the render does not wait for the network.
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/tev_protocol.h"

namespace glint::tev {

/// Where tev listens.
struct Address {
    std::string host;
    int port = kDefaultPort;
};

/// "HOST:PORT" ("[::1]:14158" for an IPv6 address). Throws glint::Error(InvalidArgument) naming
/// `where` (a flag) for a missing host or a port outside 1 … 65535.
Address parseAddress(const std::string& text, const std::string& where);

/// Told one line when the display stops working (refused, lost); called on the display's
/// thread.
using WarnFn = std::function<void(const std::string&)>;

/// A TCP connection to tev, made at the first send. When connecting or sending fails it warns
/// once and is down for good: every later send returns false at once.
class Connection {
  public:
    Connection(Address address, WarnFn warn);
    ~Connection();
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    /// Sends the packet; false when the connection is down.
    bool send(const Packet& packet);
    bool failed() const { return m_failed; }

  private:
    bool connect();
    void fail(const std::string& what);

    Address m_address;
    WarnFn m_warn;
    int m_socket = -1;
    std::atomic<bool> m_failed = false;
};

/// The tev channel names of `frame`'s layers: every layer but the half buffers, named as in
/// the layered EXR ("R", "G", "B", "variance.R", "albedo.R", …, "depth.Z"), so that tev groups
/// each layer.
std::vector<std::string> displayChannels(const FrameBuffers& frame);
/// The CreateImage of `frame` as image `name` (displayChannels, the frame's size).
CreateImage createPacket(const std::string& name, const FrameBuffers& frame);
/// `send(update)` for each tile of `frame` (tiles of at most tileSize × tileSize pixels with
/// every channel of displayChannels, in rows from the top left); stops when `send` returns
/// false, and returns false then.
bool forEachTile(const FrameBuffers& frame, const std::string& name, int tileSize,
                 const std::function<bool(const UpdateImage&)>& send);

/// Options of a Display.
struct DisplayOptions {
    Address address;
    std::string name;         ///< the image's name in tev
    bool closeAtEnd = false;  ///< finish() closes the image in tev
    int tileSize = 128;       ///< pixels per side of an update
    WarnFn warn;
};

/// Shows frames in tev: the first frame creates the image (again when the size or the layers
/// change), each frame shown is sent as updates. A frame shown while another is being sent
/// waits, and a newer one replaces it: tev sees the latest.
class Display {
  public:
    explicit Display(DisplayOptions options);
    /// finish()
    ~Display();
    Display(const Display&) = delete;
    Display& operator=(const Display&) = delete;

    /// Queues `frame` for sending (replacing one still queued).
    void show(std::shared_ptr<const FrameBuffers> frame);
    /// Sends the frame queued, closes the image when asked, and stops the thread (idempotent).
    void finish();
    /// Whether the connection failed (the warning was given).
    bool failed() const;

  private:
    void run();
    void send(const FrameBuffers& frame);

    DisplayOptions m_options;
    Connection m_connection;
    std::vector<std::string> m_created;  // channels of the image created in tev
    int m_createdWidth = 0, m_createdHeight = 0;
    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::shared_ptr<const FrameBuffers> m_pending;
    bool m_finishing = false;
    std::thread m_thread;
};

}  // namespace glint::tev
