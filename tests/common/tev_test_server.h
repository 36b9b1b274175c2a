// A stand-in for tev in the tests: listens on 127.0.0.1 at an ephemeral port (bind port 0, so
// parallel ctest runs never collide), accepts one connection on a thread of its own and decodes
// every packet it receives with Glint's decoder, the bytes kept as well.
#pragma once

#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "glint/image/tev_protocol.h"

namespace glint::testing {

class TevTestServer {
  public:
    /// `closeAfter` >= 0: the server closes the connection after that many packets (a tev that
    /// quits mid-render); else it reads until the client closes.
    explicit TevTestServer(int closeAfter = -1) : m_closeAfter(closeAfter) {
        m_listen = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        addr.sin_port = 0;
        socklen_t size = sizeof addr;
        if (m_listen < 0 || ::bind(m_listen, reinterpret_cast<sockaddr*>(&addr), size) != 0 ||
            ::listen(m_listen, 1) != 0 ||
            ::getsockname(m_listen, reinterpret_cast<sockaddr*>(&addr), &size) != 0)
            throw std::runtime_error("the test server cannot listen");
        m_port = ntohs(addr.sin_port);
        m_thread = std::thread([this] { serve(); });
    }
    ~TevTestServer() {
        if (m_thread.joinable()) m_thread.join();
        if (m_listen >= 0) ::close(m_listen);
    }

    int port() const { return m_port; }
    std::string address() const { return "127.0.0.1:" + std::to_string(m_port); }

    /// Waits until the client closed (or the server did) and returns what arrived.
    const std::vector<glint::tev::Packet>& packets() {
        if (m_thread.joinable()) m_thread.join();
        return m_packets;
    }
    /// The raw bytes of each packet, as received.
    const std::vector<std::vector<unsigned char>>& rawPackets() {
        packets();
        return m_raw;
    }
    /// A decode error, if any packet did not decode.
    const std::string& error() {
        packets();
        return m_error;
    }

  private:
    void serve() {
        // A client that never connects ends the wait after a minute (a hang guard, not a
        // timing).
        pollfd p{m_listen, POLLIN, 0};
        if (::poll(&p, 1, 60000) <= 0) return;
        const int fd = ::accept(m_listen, nullptr, nullptr);
        if (fd < 0) return;
        glint::tev::PacketStream stream;
        std::vector<unsigned char> buffer(1 << 16);
        for (;;) {
            const ssize_t n = ::recv(fd, buffer.data(), buffer.size(), 0);
            if (n <= 0) break;
            stream.append({buffer.data(), std::size_t(n)});
            try {
                while (auto bytes = stream.next()) {
                    m_packets.push_back(glint::tev::decode(*bytes));
                    m_raw.push_back(std::move(*bytes));
                    if (m_closeAfter >= 0 && int(m_packets.size()) >= m_closeAfter) {
                        ::close(fd);
                        return;
                    }
                }
            } catch (const std::exception& e) {
                m_error = e.what();
                break;
            }
        }
        ::close(fd);
    }

    int m_closeAfter;
    int m_listen = -1;
    int m_port = 0;
    std::vector<glint::tev::Packet> m_packets;
    std::vector<std::vector<unsigned char>> m_raw;
    std::string m_error;
    std::thread m_thread;
};

/// A port on 127.0.0.1 nothing listens on (bound, then released).
inline int unusedPort() {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof addr;
    ::bind(fd, reinterpret_cast<sockaddr*>(&addr), size);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size);
    ::close(fd);
    return ntohs(addr.sin_port);
}

}  // namespace glint::testing
