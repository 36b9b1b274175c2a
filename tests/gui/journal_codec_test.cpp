// The autosave journal's codec (gui/model/journal_codec): every session operation encodes to the
// JSON a journal line holds and decodes back to the same operation; an unknown one is named.
#include <QJsonDocument>
#include <QTest>

#include <variant>
#include <vector>

#include "glint/image/error.h"
#include "model/journal_codec.h"
#include "model/session_state.h"

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
            jc::Start{options,
                      {{"gaussian", {{"sigma", 2.0}}}, {"bilateral", {}}},
                      {"walls", ""},
                      "/work/banks/cornell"},
            jc::Input{},
            jc::AddLayer{"nlm", {{"radius", 3.0}, {"h", 0.25}}, true},
            jc::RemoveLayer{4},
            jc::Weights{1},
            jc::Fill{2, denoise::BrushMode::Subtract},
            jc::Stroke{3, {17.5, 0.25}, denoise::BrushMode::Add, {1.0, 2.5, 40.0, 41.0}},
            jc::Apply{{0, 2, 5}},
            jc::Undo{},
            jc::Redo{},
            jc::RenameLayer{2, "walls, σ 2"},
            jc::AddLayers{{{"gaussian", {{"sigma", 1.0}}}, {"nlm", {{"h", 0.5}}}}},
            jc::Clear{}};
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
        // The bank folder the session names (its fixed parameters are the studio's banks').
        QCOMPARE(std::get<jc::Start>(jc::decode(jc::encode(ops[0]))).bankDir,
                 std::string("/work/banks/cornell"));
        QCOMPARE(std::get<jc::RenameLayer>(jc::decode(jc::encode(ops[10]))).name,
                 std::string("walls, σ 2"));
        QCOMPARE(std::get<jc::AddLayers>(jc::decode(jc::encode(ops[11]))).layers.size(),
                 std::size_t(2));
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

    void autosCorrectionTravelsAsImagesAfterTheWeights() {
        namespace jc = journal_codec;
        // Auto Start's entry: a member, then auto's correction (its result and blend after the
        // layers' weights).
        auto correction = std::make_shared<const denoise::SessionCorrection>(
            denoise::SessionCorrection{Image(4, 3, 3, 0.5f), Image(4, 3, 3, 0.25f)});
        const std::vector<denoise::LayerSpec> layers{{"gaussian", {{"sigma", 1.0}}},
                                                     {denoise::kAutoCorrection, {}, correction}};
        std::vector<Image> images{Image(4, 3, 1, 0.5f), Image(4, 3, 1, 1.0f)};
        for (Image& image : jc::correctionImages(layers)) images.push_back(std::move(image));
        QCOMPARE(images.size(), std::size_t(4));
        const QJsonObject json = jc::encode(jc::AddLayers{layers});
        const QJsonObject read = QJsonDocument::fromJson(QJsonDocument(json).toJson()).object();
        std::vector<denoise::LayerSpec> back = std::get<jc::AddLayers>(jc::decode(read)).layers;
        QCOMPARE(back.size(), std::size_t(2));
        QVERIFY(!back[1].correction);
        jc::takeCorrections(back, images);
        QVERIFY(!back[0].correction);
        QVERIFY(back[1].correction);
        QCOMPARE(back[1].correction->result(3, 2, 1), 0.5f);
        QCOMPARE(back[1].correction->blend(3, 2, 1), 0.25f);
        // An entry without the correction's images is a Format error, not a layer without one.
        std::vector<denoise::LayerSpec> partial = std::get<jc::AddLayers>(jc::decode(read)).layers;
        images.pop_back();
        bool refused = false;
        try {
            jc::takeCorrections(partial, images);
        } catch (const Error& e) {
            refused = e.kind() == ErrorKind::Format;
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

    // Issue 47: one render-settings codec, whose name for half buffers is "halfBuffers" as in
    // scene.json and glint-render. Journals and session files written before it said
    // "halves": "0" / "1"; they still restore.
    void anOldJournalWithHalvesStillRestoresHalfBuffers() {
        namespace jc = journal_codec;
        const QJsonObject old =
            QJsonDocument::fromJson(R"({"op": "settings", "spp": "6", "seed": "1",
                "integrator": "path", "mis": "power", "halves": "1"})")
                .object();
        const render::Settings back = jc::decodeSettings(old, render::Settings{});
        QCOMPARE(back.spp, 6);
        QVERIFY(back.halfBuffers);
        render::Settings on;
        on.halfBuffers = true;
        QVERIFY(!readSettings({{"halves", "0"}}, on).halfBuffers);
        QVERIFY(readSettings({{"halves", "1"}}, render::Settings{}).halfBuffers);
        // The codec's own key wins over the old one.
        QVERIFY(!readSettings({{"halves", "1"}, {"halfBuffers", "false"}}, on).halfBuffers);
        // Written now: the codec's name and text.
        const QJsonObject now = jc::encodeSettings(back);
        QCOMPARE(now.value(QStringLiteral("halfBuffers")).toString(), QStringLiteral("true"));
        QVERIFY(!now.contains(QStringLiteral("halves")));
        std::map<std::string, std::string> state;
        writeDocumentState({}, back, state);
        QCOMPARE(state.count("halves"), std::size_t(0));
        QCOMPARE(state.at("halfBuffers"), std::string("true"));
    }

    // Issue "reliability round 3", item 4: "1e12" was read as 1 spp and "-1" as a seed without a
    // word. A session file's and a journal's settings are read with glint-render's limits, and a
    // bad one is one error naming the file, the key and what was expected.
    void badRenderSettingsInASessionOrAJournalAreOneErrorNamingFileAndKey() {
        auto refusal = [](const std::map<std::string, std::string>& state) -> QString {
            try {
                readSettings(state, render::Settings{}, "/tmp/look.glint-session.json", "/view/");
            } catch (const Error& e) {
                return QString::fromStdString(e.what());
            }
            return {};
        };
        const QString spp = refusal({{"spp", "1e12"}});
        QVERIFY2(spp.contains(QStringLiteral("look.glint-session.json")), qPrintable(spp));
        QVERIFY2(spp.contains(QStringLiteral("/view/spp")), qPrintable(spp));
        QVERIFY2(spp.contains(QStringLiteral("16777216")), qPrintable(spp));  // 2^24
        const QString seed = refusal({{"seed", "-1"}});
        QVERIFY2(seed.contains(QStringLiteral("/view/seed")), qPrintable(seed));
        QVERIFY2(seed.contains(QStringLiteral("9223372036854775807")), qPrintable(seed));
        QVERIFY(!refusal({{"spp", "0"}}).isEmpty());
        QVERIFY(!refusal({{"spp", "16777217"}}).isEmpty());
        QVERIFY(!refusal({{"spp", " 4"}}).isEmpty());
        QVERIFY(!refusal({{"seed", "9223372036854775808"}}).isEmpty());
        QVERIFY(!refusal({{"integrator", "bdpt"}}).isEmpty());
        QVERIFY(!refusal({{"mis", "max"}}).isEmpty());
        QVERIFY(!refusal({{"halves", "yes"}}).isEmpty());
        // The limits themselves are accepted.
        const render::Settings edge = readSettings(
            {{"spp", "16777216"}, {"seed", "9223372036854775807"}}, render::Settings{});
        QCOMPARE(edge.spp, render::kMaxSpp);
        QCOMPARE(edge.seed, render::kMaxSeed);

        // A journal's "settings" line names the journal and its line.
        namespace jc = journal_codec;
        QJsonObject line = jc::encodeSettings(render::Settings{});
        line.insert(QStringLiteral("spp"), QStringLiteral("1e12"));
        QString journal;
        try {
            jc::decodeSettings(line, render::Settings{}, "/tmp/4242/journal.jsonl", "line 7");
        } catch (const Error& e) {
            journal = QString::fromStdString(e.what());
        }
        QVERIFY2(journal.contains(QStringLiteral("journal.jsonl")), qPrintable(journal));
        QVERIFY2(journal.contains(QStringLiteral("line 7/spp")), qPrintable(journal));
    }

    void theReferenceRoundTripsThroughItsOwnLine() {
        namespace jc = journal_codec;
        render::LookItem wall;
        wall.name = "white";
        render::LookProperty albedo;
        albedo.name = "albedo";
        albedo.value = {0.25, 0.5, 0.75};
        wall.properties.push_back(albedo);
        ReferenceInfo rendered;
        rendered.source = ReferenceInfo::Source::Rendered;
        rendered.scene = "/scenes/cornell/scene.json";
        rendered.camera = R"({"fovY":39.3})";
        rendered.look = {wall};
        rendered.settings.spp = 1024;
        auto roundTrip = [&](const std::optional<ReferenceInfo>& info) {
            const QJsonObject json = jc::encodeReference(info);
            const QJsonObject read = QJsonDocument::fromJson(QJsonDocument(json).toJson()).object();
            // The scene's look now (another albedo) is the shape the reference's values fill.
            std::vector<render::LookItem> now{wall};
            now[0].properties[0].value = {1.0, 1.0, 1.0};
            return jc::decodeReference(read, now);
        };
        QCOMPARE(jc::encodeReference(rendered).value(QStringLiteral("op")).toString(),
                 QStringLiteral("reference"));
        const std::optional<ReferenceInfo> back = roundTrip(rendered);
        QVERIFY(back && back->source == ReferenceInfo::Source::Rendered);
        QVERIFY(back->scene == rendered.scene);
        QVERIFY(back->camera == rendered.camera);
        QCOMPARE(back->settings.spp, 1024);
        QVERIFY(back->look.at(0).properties.at(0).value == albedo.value);

        ReferenceInfo file;
        file.file = "/renders/reference.exr";
        file.identity = 0xfedcba9876543210ull;
        const std::optional<ReferenceInfo> fileBack = roundTrip(file);
        QVERIFY(fileBack && fileBack->source == ReferenceInfo::Source::File);
        QVERIFY(fileBack->file == file.file);
        QCOMPARE(fileBack->identity, file.identity);
        QVERIFY(!roundTrip(std::nullopt));  // cleared
    }

    void theViewRoundTripsAndABadOneIsNamed() {
        namespace jc = journal_codec;
        for (const std::optional<int> stage : {std::optional<int>(3), std::optional<int>()}) {
            // With the channel and without (journals written before it was kept).
            const jc::View view{
                .exposure = -2.5,
                .keepRefining = true,
                .stage = stage,
                .channel = stage ? std::optional<std::string>("sampleCount") : std::nullopt};
            const QJsonObject json = jc::encodeView(view);
            QCOMPARE(json.value(QStringLiteral("op")).toString(), QStringLiteral("view"));
            const QJsonObject read = QJsonDocument::fromJson(QJsonDocument(json).toJson()).object();
            QVERIFY(jc::decodeView(read) == view);
        }
        auto throwsNaming = [](const QByteArray& line, const char* what) {
            try {
                jc::decodeView(QJsonDocument::fromJson(line).object());
            } catch (const Error& e) {
                return QString::fromUtf8(e.what()).contains(QLatin1String(what));
            }
            return false;
        };
        QVERIFY(throwsNaming(R"({"op":"view","keepRefining":false})", "exposure"));
        QVERIFY(throwsNaming(R"({"op":"view","exposure":"1","keepRefining":false})", "exposure"));
        QVERIFY(throwsNaming(R"({"op":"view","exposure":1e999,"keepRefining":false})", "exposure"));
        QVERIFY(throwsNaming(R"({"op":"view","exposure":1,"keepRefining":1})", "keepRefining"));
        QVERIFY(throwsNaming(R"({"op":"view","exposure":1})", "keepRefining"));
        // The stage, when there is one (journals before it had none): an integer of [0, 4).
        for (const char* stage : {"4", "-1", "1.5", "\"2\"", "null", "1e9"})
            QVERIFY2(throwsNaming(QByteArray(R"({"op":"view","exposure":1,"keepRefining":true,)") +
                                      "\"stage\":" + stage + "}",
                                  "stage"),
                     stage);
        // The channel, when there is one: a name (which names are channels is the viewer's).
        for (const char* channel : {"1", "null", "[\"albedo\"]", "true"})
            QVERIFY2(throwsNaming(QByteArray(R"({"op":"view","exposure":1,"keepRefining":true,)") +
                                      "\"channel\":" + channel + "}",
                                  "channel"),
                     channel);
    }
};

}  // namespace glint::studio

QTEST_GUILESS_MAIN(glint::studio::JournalCodecTest)
#include "journal_codec_test.moc"
