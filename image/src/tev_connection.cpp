// A TCP connection to tev over POSIX sockets (glint/image/tev_client.h).
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

#include "glint/image/error.h"
#include "glint/image/tev_client.h"

namespace glint::tev {

namespace {

/// How long connecting and each send may block before the display is given up (a tev that
/// stopped reading, a host that does not answer).
constexpr int kTimeoutMs = 5000;

std::string label(const Address& a) {
    return (a.host.find(':') != std::string::npos ? "[" + a.host + "]" : a.host) + ":" +
           std::to_string(a.port);
}

/// Connects `fd` to `addr` within kTimeoutMs; 0 or an errno value.
int connectWithin(int fd, const sockaddr* addr, socklen_t length) {
    const int flags = fcntl(fd, F_GETFL, 0);
    fcntl(fd, F_SETFL, flags | O_NONBLOCK);
    int error = 0;
    if (::connect(fd, addr, length) != 0) {
        error = errno;
        if (error == EINPROGRESS) {
            pollfd p{fd, POLLOUT, 0};
            const int ready = poll(&p, 1, kTimeoutMs);
            socklen_t size = sizeof error;
            if (ready == 0)
                error = ETIMEDOUT;
            else if (ready < 0 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &size) != 0)
                error = errno;
        }
    }
    fcntl(fd, F_SETFL, flags);
    return error;
}

}  // namespace

Address parseAddress(const std::string& text, const std::string& where) {
    const auto bad = [&](const std::string& why) {
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "': " + why + " (expected HOST:PORT, e.g. 127.0.0.1:14158)",
                    "command line", where);
    };
    const std::size_t colon = text.rfind(':');
    if (colon == std::string::npos || colon == 0) bad("no host and port");
    Address a;
    a.host = text.substr(0, colon);
    if (a.host.size() > 2 && a.host.front() == '[' && a.host.back() == ']')
        a.host = a.host.substr(1, a.host.size() - 2);
    const std::string port = text.substr(colon + 1);
    const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), a.port);
    if (port.empty() || ec != std::errc() || end != port.data() + port.size() || a.port < 1 ||
        a.port > 65535)
        bad("the port must be a whole number in 1 … 65535");
    return a;
}

Connection::Connection(Address address, WarnFn warn)
    : m_address(std::move(address)), m_warn(std::move(warn)) {}

Connection::~Connection() {
    if (m_socket >= 0) ::close(m_socket);
}

void Connection::fail(const std::string& what) {
    if (m_socket >= 0) ::close(m_socket);
    m_socket = -1;
    m_failed = true;
    if (m_warn) m_warn("tev at " + label(m_address) + ": " + what + "; going on without it");
}

bool Connection::connect() {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(m_address.port);
    if (const int err = getaddrinfo(m_address.host.c_str(), port.c_str(), &hints, &found)) {
        fail(std::string("cannot resolve the host: ") + gai_strerror(err));
        return false;
    }
    int error = 0;
    for (const addrinfo* a = found; a && m_socket < 0; a = a->ai_next) {
        const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) {
            error = errno;
            continue;
        }
        error = connectWithin(fd, a->ai_addr, a->ai_addrlen);
        if (error == 0)
            m_socket = fd;
        else
            ::close(fd);
    }
    freeaddrinfo(found);
    if (m_socket < 0) {
        fail(std::strerror(error));
        return false;
    }
    timeval timeout{kTimeoutMs / 1000, 0};
    setsockopt(m_socket, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    return true;
}

bool Connection::send(const Packet& packet) {
    if (m_failed) return false;
    if (m_socket < 0 && !connect()) return false;
    const std::vector<unsigned char> bytes = encode(packet);
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        // MSG_NOSIGNAL: a closed tev is an error here, not a SIGPIPE that ends the program.
        const ssize_t n = ::send(m_socket, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            fail(std::string("the connection was lost (") +
                 (errno == EAGAIN || errno == EWOULDBLOCK ? "tev stopped reading"
                                                          : std::strerror(errno)) +
                 ")");
            return false;
        }
        sent += std::size_t(n);
    }
    return true;
}

}  // namespace glint::tev
