// The autosave journal's codec (gui/model/journal_codec): every session operation encodes to the
// JSON a journal line holds and decodes back to the same operation; an unknown one is named.
#include <QJsonDocument>
#include <QTest>

#include <variant>
#include <vector>

#include "glint/image/error.h"
#include "model/journal_codec.h"

namespace glint::studio {

class JournalCodecTest : public QObject {
    Q_OBJECT

  private slots:
    void theJournalCodecRoundTripsEveryOperation() {
        namespace jc = journal_codec;
        denoise::SessionOptions options;
        options.prefilter = true;
        options.prefilterParams = {{"sigma", 1.5}};
        const std::vector<jc::Op> ops = {
            jc::Start{options, {{"gaussian", {{"sigma", 2.0}}}, {"bilateral", {}}}, {"walls", ""}},
            jc::Input{},
            jc::AddLayer{"nlm", {{"radius", 3.0}, {"h", 0.25}}, true},
            jc::RemoveLayer{4},
            jc::Weights{1},
            jc::Fill{2, denoise::BrushMode::Subtract},
            jc::Stroke{3, {17.5, 0.25}, denoise::BrushMode::Add, {1.0, 2.5, 40.0, 41.0}},
            jc::Apply{{0, 2, 5}},
            jc::Undo{},
            jc::Redo{},
            jc::RenameLayer{2, "walls, σ 2"}};
        for (const jc::Op& op : ops) {
            const QJsonObject json = jc::encode(op);
            // Through the journal's text and back: the same operation, the same JSON.
            const QJsonObject read = QJsonDocument::fromJson(QJsonDocument(json).toJson()).object();
            const jc::Op back = jc::decode(read);
            QCOMPARE(back.index(), op.index());
            QCOMPARE(jc::encode(back), json);
        }
        const auto stroke = std::get<jc::Stroke>(jc::decode(jc::encode(ops[6])));
        QCOMPARE(stroke.brush.size, 17.5);
        QCOMPARE(stroke.dabs.size(), std::size_t(4));
        QCOMPARE(std::get<jc::Start>(jc::decode(jc::encode(ops[0]))).options.prefilterParams,
                 options.prefilterParams);
        QCOMPARE(std::get<jc::Fill>(jc::decode(jc::encode(ops[5]))).mode,
                 denoise::BrushMode::Subtract);
        QCOMPARE(std::get<jc::Start>(jc::decode(jc::encode(ops[0]))).names,
                 std::vector<std::string>({"walls", ""}));
        QCOMPARE(std::get<jc::RenameLayer>(jc::decode(jc::encode(ops[10]))).name,
                 std::string("walls, σ 2"));
        // A list-of-strings parameter (an external denoiser's command) comes back as the list.
        denoise::ParamValues external{{"format", 1.0}, {"command", 0.0}};
        external.strings["command"] = {"/opt/oidn/bin/oidnDenoise", "--hdr", "{color}", "-o",
                                       "{output}"};
        const QJsonObject added = jc::encode(jc::AddLayer{"external", external, false});
        const QJsonObject addedRead =
            QJsonDocument::fromJson(QJsonDocument(added).toJson()).object();
        QVERIFY(std::get<jc::AddLayer>(jc::decode(addedRead)).params == external);
        // An operation it does not know is named.
        bool refused = false;
        try {
            jc::decode({{QStringLiteral("op"), QStringLiteral("teleport")}});
        } catch (const Error& e) {
            refused = QString::fromStdString(e.what()).contains(QStringLiteral("teleport"));
        }
        QVERIFY(refused);
    }

    void renderSettingsRoundTripThroughTheirOwnLine() {
        namespace jc = journal_codec;
        render::Settings s;
        s.spp = 7;
        s.seed = 42;
        s.integrator = render::Integrator::Mlt;
        s.mis = render::MisHeuristic::Balance;
        s.halfBuffers = true;
        const QJsonObject json = jc::encodeSettings(s);
        QCOMPARE(json.value(QStringLiteral("op")).toString(), QStringLiteral("settings"));
        const QJsonObject read = QJsonDocument::fromJson(QJsonDocument(json).toJson()).object();
        const render::Settings back = jc::decodeSettings(read, render::Settings{});
        QCOMPARE(back.spp, 7);
        QCOMPARE(back.seed, std::uint64_t(42));
        QCOMPARE(back.integrator, render::Integrator::Mlt);
        QCOMPARE(back.mis, render::MisHeuristic::Balance);
        QVERIFY(back.halfBuffers);
        // A key missing leaves the value as it was.
        QJsonObject partial = json;
        partial.remove(QStringLiteral("spp"));
        QCOMPARE(jc::decodeSettings(partial, render::Settings{}).spp, render::Settings{}.spp);
    }
};

}  // namespace glint::studio

QTEST_GUILESS_MAIN(glint::studio::JournalCodecTest)
#include "journal_codec_test.moc"
