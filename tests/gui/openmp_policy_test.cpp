// The studio's passive OpenMP wait (gui/app/openmp_policy.h): the decision keeps a user's
// OMP_WAIT_POLICY; a failed exec goes on as launched; and the built glint-studio, started
// without the variable, runs with libgomp's passive wait (libgomp's own OMP_DISPLAY_ENV=verbose
// report of each load: GOMP_SPINCOUNT 0 is passive, 300000 its default, 3e10 active), while a
// user's value is what libgomp reads, in a process started once; and the process run again
// gives what it starts the user's environment back.
#include <QProcess>
#include <QRegularExpression>
#include <QTest>

#include <cstdlib>

#include "app/openmp_policy.h"

namespace glint::studio {

namespace {

/// What libgomp reported of each load in `process`'s stderr: the GOMP_SPINCOUNT of each.
QStringList spinCounts(const QString& stderrText) {
    QStringList counts;
    const QRegularExpression line(QStringLiteral("GOMP_SPINCOUNT = '(\\d+)'"));
    for (auto it = line.globalMatch(stderrText); it.hasNext();) counts << it.next().captured(1);
    return counts;
}

/// glint-studio --version with `policy` as OMP_WAIT_POLICY (null: unset) and libgomp's report
/// on; its stderr (after checking it printed its version and exited 0).
QString runStudio(const char* policy) {
    QProcess studio;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.remove(QStringLiteral("OMP_WAIT_POLICY"));
    env.remove(QStringLiteral("GOMP_SPINCOUNT"));
    if (policy) env.insert(QStringLiteral("OMP_WAIT_POLICY"), QString::fromUtf8(policy));
    env.insert(QStringLiteral("OMP_DISPLAY_ENV"), QStringLiteral("verbose"));
    env.insert(QStringLiteral("QT_QPA_PLATFORM"), QStringLiteral("offscreen"));
    studio.setProcessEnvironment(env);
    studio.start(QStringLiteral(GLINT_STUDIO_EXE), {QStringLiteral("--version")});
    if (!studio.waitForFinished(120000)) return QStringLiteral("(did not finish)");
    const QString out = QString::fromUtf8(studio.readAllStandardOutput());
    if (studio.exitStatus() != QProcess::NormalExit || studio.exitCode() != 0 ||
        !out.contains(QStringLiteral("Glint Studio")))
        return QStringLiteral("(failed: %1)").arg(out);
    return QString::fromUtf8(studio.readAllStandardError());
}

}  // namespace

class OpenMpPolicyTest : public QObject {
    Q_OBJECT

  private slots:
    void onlyAnUnsetVariableMakesTheProcessRunAgain() {
        QVERIFY(runAgainForPassiveWait(nullptr));
        QVERIFY(!runAgainForPassiveWait("ACTIVE"));
        QVERIFY(!runAgainForPassiveWait("active"));
        QVERIFY(!runAgainForPassiveWait("PASSIVE"));
        QVERIFY(!runAgainForPassiveWait(""));
    }

    void aFailedExecGoesOnWithTheVariableUnsetAgain() {
        unsetenv("OMP_WAIT_POLICY");
        char name[] = "openmp_policy_tests";
        char* argv[] = {name, nullptr};
        usePassiveOpenMpWait(argv, "/nonexistent/glint-studio");
        QVERIFY(std::getenv("OMP_WAIT_POLICY") == nullptr);
        QVERIFY(std::getenv("GLINT_STUDIO_SET_OMP_WAIT_POLICY") == nullptr);
        // A user's value: nothing is run, the value stays.
        setenv("OMP_WAIT_POLICY", "ACTIVE", 1);
        usePassiveOpenMpWait(argv, "/nonexistent/glint-studio");
        QCOMPARE(QString::fromUtf8(std::getenv("OMP_WAIT_POLICY")), QStringLiteral("ACTIVE"));
        unsetenv("OMP_WAIT_POLICY");
    }

    void theProcessRunAgainGivesItsChildrenTheUsersEnvironment() {
        // As the studio finds them after its exec: the variable and the marker are taken out,
        // and nothing is run again (an exec of /bin/false would end this test with exit 1).
        setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
        setenv("GLINT_STUDIO_SET_OMP_WAIT_POLICY", "1", 1);
        char name[] = "openmp_policy_tests";
        char* argv[] = {name, nullptr};
        usePassiveOpenMpWait(argv, "/bin/false");
        QVERIFY(std::getenv("OMP_WAIT_POLICY") == nullptr);
        QVERIFY(std::getenv("GLINT_STUDIO_SET_OMP_WAIT_POLICY") == nullptr);
        // The marker is set only with the studio's own value: a user's value has none and stays.
        setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
        usePassiveOpenMpWait(argv, "/bin/false");
        QCOMPARE(QString::fromUtf8(std::getenv("OMP_WAIT_POLICY")), QStringLiteral("PASSIVE"));
        unsetenv("OMP_WAIT_POLICY");
    }

    void theStudioRunsWithThePassiveWait() {
        // Loaded twice (as launched, then run again): the second load's libgomp is passive.
        const QString err = runStudio(nullptr);
        QCOMPARE(spinCounts(err), (QStringList{QStringLiteral("300000"), QStringLiteral("0")}));
    }

    void aUsersWaitPolicyIsWhatTheStudioRunsWith() {
        // Loaded once, with the user's value.
        QCOMPARE(spinCounts(runStudio("ACTIVE")), QStringList{QStringLiteral("30000000000")});
        QCOMPARE(spinCounts(runStudio("PASSIVE")), QStringList{QStringLiteral("0")});
    }
};

}  // namespace glint::studio

QTEST_GUILESS_MAIN(glint::studio::OpenMpPolicyTest)
#include "openmp_policy_test.moc"
