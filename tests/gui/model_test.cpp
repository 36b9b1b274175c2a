// The studio's bank service: one bank build serves Navigate and Auto Start, requests of the same
// bank share its build, and a new render builds again.
#include "model_test.h"

#include <QDir>
#include <QTemporaryDir>
#include <QTest>

#include <map>
#include <string>

#include "glint/denoise/session.h"
#include "model/learned_member.h"
#include "studio_fixture.h"
#include "views/navigate_view.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// The bank Auto Start asks for (64 members over the whole frame, the session's prefiltering).
denoise::BankOptions autoStartBank(SessionAdapter& s) {
    denoise::BankOptions o;
    o.size = 64;
    o.filters = studioBankFilters();  // the learned filter too, when it runs here
    o.prefilter = s.options().prefilter;
    o.prefilterParams = s.options().prefilterParams;
    return o;
}

}  // namespace

class StudioModelTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;

    std::unique_ptr<MainWindow> openScene(const QString& autosave) {
        return openAndWait(m_scene, m_dir.filePath(autosave));
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void navigateThenAutoStartBuildTheBankOnce() {
        auto w = openScene(QStringLiteral("autosave-bank1"));
        QVERIFY(w);
        BankService* banks = w->session()->banks();
        const int before = banks->builds();
        // Navigate over the whole image with Auto Start's bank size: the same bank.
        w->navigateView()->setBankSize(64);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        QCOMPARE(banks->builds(), before + 1);
        const BankService::BankPtr bank =
            banks->cached(w->session()->input(), autoStartBank(*w->session()));
        QVERIFY(bank);
        w->actions().autoStart->trigger();
        const denoise::Session& s = w->session()->session();
        QVERIFY(waitFor([&] { return s.layerCount() > 0 && !w->session()->busy(); }, 60000));
        QCOMPARE(banks->builds(), before + 1);  // Auto Start took Navigate's bank
        QCOMPARE(banks->cached(w->session()->input(), autoStartBank(*w->session())), bank);
        QVERIFY(w->lastError().isEmpty());

        // A new render: its bank is built again (once), and the old one is dropped.
        const FramePtr old = w->session()->input();
        render::Settings settings = w->document()->settings();
        settings.seed = 9;
        w->document()->setSettings(settings);
        w->document()->render();
        QVERIFY(waitFor([&] { return w->session()->input() != old; }, 60000));
        QVERIFY(waitIdle(*w));
        QVERIFY(!banks->cached(old, autoStartBank(*w->session())));
        w->actions().autoStart->trigger();
        QVERIFY(waitFor([&] { return banks->builds() == before + 2; }, 60000));
        QVERIFY(waitFor([&] { return !w->session()->busy(); }, 60000));
        w->setStage(2, true);  // Navigate is stale: it asks again and gets Auto Start's bank
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        QCOMPARE(banks->builds(), before + 2);
        QVERIFY(w->lastError().isEmpty());
    }

    void autoStartThenNavigateBuildTheBankOnce() {
        auto w = openScene(QStringLiteral("autosave-bank2"));
        QVERIFY(w);
        BankService* banks = w->session()->banks();
        const int before = banks->builds();
        w->actions().autoStart->trigger();
        const denoise::Session& s = w->session()->session();
        QVERIFY(waitFor([&] { return s.layerCount() > 0 && !w->session()->busy(); }, 60000));
        QCOMPARE(banks->builds(), before + 1);
        w->navigateView()->setBankSize(64);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        QCOMPARE(banks->builds(), before + 1);
        // Another size is another bank.
        w->navigateView()->setBankSize(8);
        w->navigateView()->build();
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        QCOMPARE(banks->builds(), before + 2);
    }

    void aSessionsBankFolderGivesTheStudiosBanksItsFixedParameters() {
        auto w = openScene(QStringLiteral("autosave-bank-params"));
        QVERIFY(w);
        // A bank folder of the render made with fixed parameters (glint-denoise bank
        // --filter-param bilateral.sigmaS=2, and unet's small weights when it runs here), and a
        // session naming it.
        std::map<std::string, denoise::ParamValues> fixed{{"bilateral", {{"sigmaS", 2.0}}}};
        if (learnedFilterAvailable()) fixed[kLearnedFilter] = {{"quality", 0.0}};
        denoise::BankOptions made;
        made.size = 4;
        made.filterParams = fixed;
        made.cacheDir = m_dir.filePath(QStringLiteral("params-bank")).toStdString();
        QVERIFY(QDir().mkpath(QString::fromStdString(made.cacheDir.string())));
        (void)denoise::buildBank(*w->session()->input(), made);
        denoise::Session named(*w->session()->input());
        named.bankDir = made.cacheDir;
        const QString file = m_dir.filePath(QStringLiteral("params.glint-session.json"));
        named.save(file.toStdString());
        bool loaded = false;
        connect(w->session(), &SessionAdapter::loaded, this, [&] { loaded = true; });
        w->session()->load(file);
        QVERIFY(waitFor([&] { return loaded && !w->session()->busy(); }, 60000));

        // Navigate and Auto Start share one bank, and it holds the folder's parameters.
        BankService* banks = w->session()->banks();
        const int before = banks->builds();
        w->navigateView()->setBankSize(64);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        w->actions().autoStart->trigger();
        QVERIFY(waitFor(
            [&] { return w->session()->session().layerCount() > 0 && !w->session()->busy(); },
            60000));
        QCOMPARE(banks->builds(), before + 1);
        QVERIFY(w->lastError().isEmpty());
        const FramePtr in = w->session()->input();
        denoise::BankOptions withParams = autoStartBank(*w->session());
        withParams.filterParams = fixed;
        const BankService::BankPtr bank = banks->cached(in, withParams);
        QVERIFY(bank);
        // Without the parameters it is another bank, not built.
        QVERIFY(!banks->cached(in, autoStartBank(*w->session())));
        int held = 0;
        for (const denoise::BankMember& m : bank->members())
            for (const auto& [filter, params] : fixed) {
                if (m.filter != filter) continue;
                for (const auto& [name, value] : params) QCOMPARE(m.params.at(name), value);
                ++held;
            }
        QVERIFY(held >= int(fixed.size()));
    }

    void banksWithOtherFixedParametersAreOtherBanks() {
        auto w = openScene(QStringLiteral("autosave-bank-params2"));
        QVERIFY(w);
        BankService* banks = w->session()->banks();
        const FramePtr frame = w->session()->input();
        denoise::BankOptions plain;
        plain.size = 4;
        plain.filters = {"gaussian", "bilateral"};
        denoise::BankOptions fixed = plain;
        fixed.filterParams["bilateral"] = {{"sigmaS", 2.0}};
        const int before = banks->builds();
        BankService::BankPtr a, b;
        banks->request(frame, plain, this, {[&](BankService::BankPtr x) { a = x; }, {}, {}});
        QVERIFY(waitFor([&] { return a != nullptr; }, 60000));
        banks->request(frame, fixed, this, {[&](BankService::BankPtr x) { b = x; }, {}, {}});
        QVERIFY(waitFor([&] { return b != nullptr; }, 60000));
        QCOMPARE(banks->builds(), before + 2);
        QVERIFY(a != b);
        for (const denoise::BankMember& m : b->members())
            if (m.filter == "bilateral") QCOMPARE(m.params.at("sigmaS"), 2.0);
        QCOMPARE(banks->cached(frame, fixed), b);
        QCOMPARE(banks->cached(frame, plain), a);
    }

    void requestsOfOneBankShareItsBuild() {
        auto w = openScene(QStringLiteral("autosave-bank3"));
        QVERIFY(w);
        BankService* banks = w->session()->banks();
        const FramePtr frame = w->session()->input();
        denoise::BankOptions o;
        o.size = 6;
        const int before = banks->builds();
        BankService::BankPtr a, b;
        banks->request(frame, o, this, {[&](BankService::BankPtr x) { a = x; }, {}, {}});
        o.region = Rect{0, frame->width(), 0, frame->height()};  // the whole frame: the same
        banks->request(frame, o, this, {[&](BankService::BankPtr x) { b = x; }, {}, {}});
        // A withdrawn request hears nothing.
        bool withdrawnCalled = false;
        const BankService::Ticket t = banks->request(
            frame, o, this, {[&](BankService::BankPtr) { withdrawnCalled = true; }, {}, {}});
        banks->withdraw(t);
        QVERIFY(waitFor([&] { return a && b; }, 60000));
        QCOMPARE(banks->builds(), before + 1);
        QCOMPARE(a, b);
        QVERIFY(!withdrawnCalled);
        // A bank nobody waits for any more is cancelled, not kept.
        o.size = 7;
        banks->withdraw(banks->request(frame, o, this, {}));
        QVERIFY(waitFor([&] { return !banks->busy(); }, 60000));
        QVERIFY(!banks->cached(frame, o));
        QCOMPARE(banks->builds(), before + 2);
        // Another frame drops the banks of this one.
        banks->setFrame(nullptr);
        o.size = 6;
        QVERIFY(!banks->cached(frame, o));
    }
};

std::unique_ptr<QObject> makeStudioModelTest() {
    return std::make_unique<StudioModelTest>();
}

#include "model_test.moc"
