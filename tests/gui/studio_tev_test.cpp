// The studio and tev's protocol: a tev client's image grows in the studio as one document, a
// malformed packet is dropped with one log line (never a crash), and the studio's renders reach
// a stand-in tev (tests/common/tev_test_server.h). Ports are ephemeral (port 0).
#include <QApplication>
#include <QDebug>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QTcpSocket>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <cstring>
#include <vector>

#include "glint/image/tev_client.h"
#include "glint/image/tev_protocol.h"
#include "model/tev_listener.h"
#include "studio_fixture.h"
#include "tev_test_server.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

std::unique_ptr<MainWindow> listeningWindow(const QString& autosave) {
    StudioOptions options;
    options.autosaveBase = autosave;
    options.offerRestore = false;
    options.confirmDiscard = false;
    options.denoiseFirstImage = false;
    options.tevListenPort = 0;
    auto w = std::make_unique<MainWindow>(options);
    w->show();
    return w;
}

/// Row `y` of the document's colour is `value` everywhere.
bool rowIs(const Document& d, int y, float value) {
    const FramePtr f = d.finishedFrame();
    if (!f || y >= f->height()) return false;
    for (int x = 0; x < f->width(); ++x)
        for (int c = 0; c < 3; ++c)
            if (f->color()(x, y, c) != value) return false;
    return true;
}

/// The red channel of the document's colour at (x, y) is `value`.
bool shows(const Document& d, int x, int y, float value) {
    const FramePtr f = d.finishedFrame();
    return f && x < f->width() && y < f->height() && f->color()(x, y, 0) == value;
}

/// A raw connection to the studio: the test writes any bytes it likes.
struct RawClient {
    QTcpSocket socket;
    explicit RawClient(quint16 port) {
        socket.connectToHost(QStringLiteral("127.0.0.1"), port);
        socket.waitForConnected(10000);
    }
    void send(const std::vector<unsigned char>& bytes) {
        socket.write(reinterpret_cast<const char*>(bytes.data()), qint64(bytes.size()));
        socket.flush();
    }
};

}  // namespace

class StudioTevTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;

  private slots:
    void initTestCase() { QVERIFY(m_dir.isValid()); }

    void threeUpdatesFromATevClientGrowOneImageInTheStudio() {
        auto w = listeningWindow(m_dir.filePath(QStringLiteral("autosave-grow")));
        QVERIFY(w->tevListener());
        const quint16 port = w->tevListener()->port();
        QVERIFY(port > 0);
        QSignalSpy opened(w->document(), &Document::opened);
        QSignalSpy shown(w->tevListener(), &TevListener::imageShown);
        std::vector<std::string> warnings;
        tev::Connection client({"127.0.0.1", port},
                               [&](const std::string& line) { warnings.push_back(line); });
        QVERIFY(client.send(tev::CreateImage{"pbrt (7)", true, 6, 3, {"R", "G", "B"}}));
        // Three updates, a row each: the one image grows row by row.
        for (int k = 0; k < 3; ++k) {
            tev::UpdateImage u{"pbrt (7)", false, {"R", "G", "B"}, 0, k, 6, 1, {}};
            u.pixels.assign(6 * 3, float(k + 1));
            QVERIFY(client.send(u));
            QVERIFY(waitFor([&] { return rowIs(*w->document(), k, float(k + 1)); }, 60000));
            QCOMPARE(w->document()->path(), TevListener::documentPath(QStringLiteral("pbrt (7)")));
            QCOMPARE(w->document()->kind(), Document::Kind::Exr);
            for (int y = 0; y < k; ++y) QVERIFY(rowIs(*w->document(), y, float(y + 1)));
            for (int y = k + 1; y < 3; ++y) QVERIFY(rowIs(*w->document(), y, 0.0f));
        }
        QCOMPARE(opened.count(), 1);  // one document, its frame replaced
        // What the studio denoises and paints is the received image.
        QVERIFY(waitFor([&] { return w->session()->input() == w->document()->finishedFrame(); },
                        60000));
        QVERIFY(client.send(tev::CloseImage{"pbrt (7)"}));
        QVERIFY(waitFor([&] { return !shown.isEmpty() && shown.last().at(1).toBool(); }, 60000));
        QVERIFY(warnings.empty());
        QVERIFY(w->lastError().isEmpty());
    }

    void malformedPacketsAreDroppedWithOneLogLineEachAndTheStudioGoesOn() {
        auto w = listeningWindow(m_dir.filePath(QStringLiteral("autosave-bad")));
        const quint16 port = w->tevListener()->port();
        QSignalSpy log(w->tevListener(), &TevListener::logLine);
        RawClient raw(port);
        QVERIFY(raw.socket.state() == QAbstractSocket::ConnectedState);
        QVERIFY(waitFor([&] { return log.count() >= 1; }, 60000));  // "a client connected"
        log.clear();
        const auto expectDropped = [&](const std::vector<unsigned char>& bytes, const char* says) {
            const int before = int(log.count());
            raw.send(bytes);
            if (!waitFor([&] { return log.count() > before; }, 60000)) return false;
            const QString line = log.at(before).at(0).toString();
            if (!line.contains(QLatin1String(says))) qWarning() << "log line:" << line;
            return log.count() == before + 1 && line.contains(QLatin1String(says));
        };
        tev::UpdateImage outside{"i", false, {"R"}, 3, 0, 2, 1, {1.f, 1.f}};
        std::vector<unsigned char> wrongType = tev::encode(tev::CloseImage{"i"});
        wrongType[4] = 42;
        std::vector<unsigned char> huge =
            tev::encode(tev::CreateImage{"h", false, 1, 1, {"R", "G", "B"}});
        const std::int32_t big = 1 << 20;
        std::memcpy(huge.data() + 8, &big, 4);  // width past 65536: 4, 1, "h\0", then width
        QVERIFY(expectDropped(wrongType, "unknown packet type 42"));
        QVERIFY(expectDropped(huge, "65536"));
        QVERIFY(expectDropped(tev::encode(outside), "no image of this name"));
        raw.send(tev::encode(tev::CreateImage{"i", false, 4, 2, {"R", "G", "B"}}));
        outside.channels = {"R"};
        QVERIFY(expectDropped(tev::encode(outside), "outside the 4x2 image"));
        std::vector<unsigned char> truncated =
            tev::encode(tev::UpdateImage{"i", false, {"R"}, 0, 0, 2, 1, {1.f, 1.f}});
        truncated.resize(truncated.size() - 3);
        const auto length = std::uint32_t(truncated.size());
        std::memcpy(truncated.data(), &length, 4);
        QVERIFY(expectDropped(truncated, "reads past"));
        // The connection still works: a good update shows.
        raw.send(tev::encode(tev::UpdateImage{"i", false, {"G"}, 1, 1, 1, 1, {5.f}}));
        QVERIFY(waitFor(
            [&] {
                const FramePtr f = w->document()->finishedFrame();
                return f && f->color()(1, 1, 1) == 5.0f;
            },
            60000));
        // A length field no packet has: the client is dropped, the studio listens on.
        QVERIFY(expectDropped({0, 0, 0, 0, 4}, "dropped the client"));
        QVERIFY(waitFor([&] { return raw.socket.state() == QAbstractSocket::UnconnectedState; },
                        60000));
        RawClient again(port);
        QVERIFY(again.socket.state() == QAbstractSocket::ConnectedState);
        QVERIFY(w->lastError().isEmpty());
    }

    void aReceivedImageAndItsStrokeComeBackFromTheAutosave() {
        const QString base = m_dir.filePath(QStringLiteral("autosave-received"));
        const QString crashed = m_dir.filePath(QStringLiteral("received-crash"));
        const QString name = QStringLiteral("pbrt (9)");
        // Two updates (the second replaces the top half): the image as its client left it.
        const int width = 24, height = 16;
        std::vector<float> pixels(std::size_t(width) * height * 3);
        for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i % 97) / 97.0f;
        std::vector<float> top(pixels.begin(), pixels.begin() + std::ptrdiff_t(width * 8 * 3));
        for (float& v : top) v += 0.5f;
        Image weights, composite;
        {
            auto w = listeningWindow(base);
            tev::Connection client({"127.0.0.1", w->tevListener()->port()},
                                   [](const std::string&) {});
            QVERIFY(
                client.send(tev::CreateImage{"pbrt (9)", true, width, height, {"R", "G", "B"}}));
            QVERIFY(client.send(
                tev::UpdateImage{"pbrt (9)", false, {"R", "G", "B"}, 0, 0, width, height, pixels}));
            QVERIFY(waitFor(
                [&] {
                    return shows(*w->document(), width - 1, height - 1, pixels[pixels.size() - 3]);
                },
                60000));
            QVERIFY(waitIdle(*w, 60000));
            // The top half in two updates of four rows each: two "pixels" entries.
            for (int y0 = 0; y0 < 8; y0 += 4) {
                const auto rows = top.begin() + std::ptrdiff_t(y0 * width * 3);
                QVERIFY(
                    client.send(tev::UpdateImage{"pbrt (9)",
                                                 false,
                                                 {"R", "G", "B"},
                                                 0,
                                                 y0,
                                                 width,
                                                 4,
                                                 {rows, rows + std::ptrdiff_t(4 * width * 3)}}));
                QVERIFY(waitFor([&] { return shows(*w->document(), 0, y0, *rows); }, 60000));
                QVERIFY(waitIdle(*w, 60000));
            }
            // The artist adds a layer and paints a stroke on it.
            QVERIFY(addGaussian(*w, false));
            QVERIFY(waitIdle(*w, 60000));
            const std::size_t layer = w->session()->session().layerCount() - 1;
            w->session()->beginStroke(layer, {6.0, 0.5}, denoise::BrushMode::Add);
            for (double x = 4.0; x < 20.0; x += 2.0) w->session()->dab(x, 8.0);
            w->session()->endStroke();
            QVERIFY(waitIdle(*w, 60000));
            weights = w->session()->session().layer(layer).weights;
            composite = w->session()->session().composite();
            QVERIFY(std::any_of(weights.data().begin(), weights.data().end(),
                                [](float v) { return v > 0.0f; }));
            // A crash here: the autosave as it is on disk, kept where the next studio looks.
            w->autosave()->flush();
            const QDir journal(
                QDir(base).filePath(QString::number(QCoreApplication::applicationPid())));
            QVERIFY(QDir().mkpath(crashed));
            for (const QString& file : journal.entryList(QDir::Files))
                QVERIFY(QFile::copy(journal.filePath(file), QDir(crashed).filePath(file)));
            // Of the client's updates only the latest render is kept on disk.
            QFile lines(journal.filePath(QStringLiteral("journal.jsonl")));
            QVERIFY(lines.open(QIODevice::ReadOnly));
            QStringList updates;
            for (const QByteArray& line : lines.readAll().split('\n')) {
                const QJsonObject op = QJsonDocument::fromJson(line).object();
                if (op.value(QStringLiteral("op")).toString() == QStringLiteral("pixels"))
                    updates << op.value(QStringLiteral("render")).toString();
            }
            QVERIFY2(updates.size() >= 2, qPrintable(updates.join(QLatin1Char(' '))));
            for (int i = 0; i < updates.size(); ++i)
                QCOMPARE(QFile::exists(journal.filePath(updates[i])), i == updates.size() - 1);
        }
        // A fresh studio reopens it: the same image, the same layer and stroke.
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave-reopened")));
        w->restoreFrom(crashed);
        QVERIFY(waitFor([&] { return !w->autosave()->restoring(); }, 120000));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        QVERIFY(waitIdle(*w, 60000));
        QCOMPARE(w->document()->path(), TevListener::documentPath(name));
        QCOMPARE(w->document()->kind(), Document::Kind::Exr);
        const FramePtr frame = w->document()->finishedFrame();
        QVERIFY(frame && frame->width() == width && frame->height() == height);
        std::vector<float> want = pixels;
        std::copy(top.begin(), top.end(), want.begin());
        QVERIFY(std::equal(want.begin(), want.end(), frame->color().data().begin()));
        const denoise::Session& got = w->session()->session();
        QVERIFY(got.layerCount() >= 1);
        QVERIFY(sameBits(got.layer(got.layerCount() - 1).weights, weights));
        QVERIFY(sameBits(got.composite(), composite));
    }

    void theStudiosRenderPassesReachTevWhenAsked() {
        glint::testing::TevTestServer tev;
        const QString scene = writeSmallCornell(m_dir);
        {
            StudioOptions options;
            options.autosaveBase = m_dir.filePath(QStringLiteral("autosave-send"));
            options.offerRestore = false;
            options.confirmDiscard = false;
            options.denoiseFirstImage = false;
            options.tevDisplay = QString::fromStdString(tev.address());
            MainWindow w(options);
            w.show();
            w.openFile(scene);
            QVERIFY(waitIdle(w, 60000));
        }  // the window ends: the sender finishes and disconnects
        const auto& packets = tev.packets();
        QCOMPARE(QString::fromStdString(tev.error()), QString());
        QVERIFY(packets.size() >= 2);
        const auto* create = std::get_if<tev::CreateImage>(&packets[0]);
        QVERIFY(create);
        QCOMPARE(QString::fromStdString(create->name), QFileInfo(scene).fileName());
        QVERIFY(create->channels.size() > 3);
        for (std::size_t i = 1; i < packets.size(); ++i)
            QVERIFY(std::holds_alternative<tev::UpdateImage>(packets[i]));
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioTevTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_tev_test.moc"
