// One pass over JSON text without recursion and without a document: the text may come in
// pieces (a file read a block at a time), and each bracket, key, string and scalar is reported
// with its depth and place as it ends. Lenient: it classifies what it sees and checks nothing
// (the parser that reads the text afterwards names what is malformed). Used by the glTF nesting
// check (gltf_document.h) and by the glTF load's memory prediction (load_memory.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace glint::render::detail {

/// One token of a JsonScan.
struct JsonToken {
    enum class Kind { Open, Close, Key, String, Scalar };
    Kind kind = Kind::Scalar;
    bool array = false;  ///< Open, Close: a '[' or ']' (else '{' or '}')
    /// Key, String, Scalar: the token's first JsonScan::kTextCap bytes as written (a string
    /// without its quotes, escapes as written).
    std::string_view text;
    std::uint64_t length = 0;  ///< Key, String, Scalar: the whole token's length
    /// Containers open around the token; for Open the new one included, for Close the closed one.
    int depth = 0;
    std::uint64_t byte = 0;  ///< of the token's first character, counted from the first piece
    std::size_t line = 1, column = 0;  ///< of that character (column 1-based)
};

/// The scan's state between pieces. `onToken(const JsonToken&, const JsonScan&)` is called for
/// each token; it may throw to stop the scan.
class JsonScan {
  public:
    /// The most bytes of a key, string or scalar a token holds.
    static constexpr std::size_t kTextCap = 96;
    /// The containers whose key and element index frame() remembers (deeper ones only count).
    static constexpr int kFrames = 16;

    /// What the scan knows of an open container: array or object, the key of its member being
    /// read (objects), the index of its element being read (arrays; -1 before the first).
    struct Frame {
        bool array = false;
        bool expectKey = false;
        std::string key;
        std::int64_t index = -1;
    };

    /// Scans the next piece of the text.
    template <class OnToken>
    void feed(std::string_view piece, OnToken&& onToken);
    /// Ends the text (reports a scalar it ends).
    template <class OnToken>
    void finish(OnToken&& onToken) {
        if (m_in == In::Scalar) endScalar(onToken);
    }

    /// Containers open now.
    int depth() const { return m_depth; }
    /// The container at depth d (1: the outermost), for d <= min(depth(), kFrames).
    const Frame& frame(int d) const { return m_frames[std::size_t(d - 1)]; }

  private:
    enum class In { Between, String, Scalar };
    /// A value starts in the innermost container: its element index moves on.
    void startValue() {
        if (m_depth >= 1 && m_depth <= kFrames) {
            Frame& f = m_frames[std::size_t(m_depth - 1)];
            if (f.array) ++f.index;
        }
    }
    bool expectingKey() const {
        return m_depth >= 1 && m_depth <= kFrames && m_frames[std::size_t(m_depth - 1)].expectKey;
    }
    void begin(In in, char c) {
        m_in = in;
        m_text.clear();
        if (in == In::Scalar) m_text.push_back(c);
        m_length = in == In::Scalar ? 1 : 0;
        m_start = m_token;
    }
    template <class OnToken>
    void endScalar(OnToken& onToken) {
        m_in = In::Between;
        m_start.kind = JsonToken::Kind::Scalar;
        m_start.text = m_text;
        m_start.length = m_length;
        m_start.depth = m_depth;
        onToken(m_start, *this);
    }

    In m_in = In::Between;
    bool m_escaped = false;
    int m_depth = 0;
    std::vector<Frame> m_frames;
    std::string m_text;
    std::uint64_t m_length = 0;
    std::uint64_t m_byte = 0;
    std::size_t m_line = 1, m_column = 0;
    JsonToken m_token, m_start;
};

template <class OnToken>
void JsonScan::feed(std::string_view piece, OnToken&& onToken) {
    for (const char c : piece) {
        ++m_column;
        if (c == '\n') ++m_line, m_column = 0;
        m_token.byte = m_byte++;
        m_token.line = m_line;
        m_token.column = m_column;
        if (m_in == In::String) {
            if (m_escaped) {
                m_escaped = false;
            } else if (c == '\\') {
                m_escaped = true;
            } else if (c == '"') {
                m_in = In::Between;
                const bool key = expectingKey();
                if (key) {
                    Frame& f = m_frames[std::size_t(m_depth - 1)];
                    f.expectKey = false;
                    f.key.assign(m_text);
                }
                m_start.kind = key ? JsonToken::Kind::Key : JsonToken::Kind::String;
                m_start.text = m_text;
                m_start.length = m_length;
                m_start.depth = m_depth;
                onToken(m_start, *this);
                continue;
            }
            if (m_text.size() < kTextCap) m_text.push_back(c);
            ++m_length;
            continue;
        }
        const bool structural = c == '[' || c == '{' || c == ']' || c == '}' || c == ',' ||
                                c == ':' || c == '"' || c == ' ' || c == '\n' || c == '\r' ||
                                c == '\t';
        if (m_in == In::Scalar) {
            if (!structural) {
                if (m_text.size() < kTextCap) m_text.push_back(c);
                ++m_length;
                continue;
            }
            endScalar(onToken);
        }
        switch (c) {
            case '"':
                if (!expectingKey()) startValue();
                begin(In::String, c);
                break;
            case '[':
            case '{': {
                startValue();
                ++m_depth;
                if (m_depth <= kFrames) {
                    if (m_frames.size() < std::size_t(m_depth))
                        m_frames.resize(std::size_t(m_depth));
                    Frame& f = m_frames[std::size_t(m_depth - 1)];
                    f.array = c == '[';
                    f.expectKey = c == '{';
                    f.key.clear();
                    f.index = -1;
                }
                JsonToken t = m_token;
                t.kind = JsonToken::Kind::Open;
                t.array = c == '[';
                t.depth = m_depth;
                onToken(t, *this);
                break;
            }
            case ']':
            case '}':
                if (m_depth > 0) {
                    JsonToken t = m_token;
                    t.kind = JsonToken::Kind::Close;
                    t.array = c == ']';
                    t.depth = m_depth;
                    --m_depth;
                    onToken(t, *this);
                }
                break;
            case ',':
                if (m_depth >= 1 && m_depth <= kFrames) {
                    Frame& f = m_frames[std::size_t(m_depth - 1)];
                    f.expectKey = !f.array;
                }
                break;
            case ':':
            case ' ':
            case '\n':
            case '\r':
            case '\t':
                break;
            default:
                startValue();
                begin(In::Scalar, c);
                break;
        }
    }
}

}  // namespace glint::render::detail
