// glint-studio [SCENE.json | IMAGE.exr | SESSION.glint-session.json]
#include <QApplication>
#include <QCommandLineParser>
#include <QTimer>

#include <cstdio>
#include <exception>

#include "app/main_window.h"
#include "app/studio_settings.h"

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("Glint"));
    QApplication::setApplicationName(QStringLiteral("Glint Studio"));
    QApplication::setApplicationVersion(QStringLiteral("0.1"));
    // External denoisers run only the programs the user allowed (docs/external-denoiser.md).
    glint::studio::applyAllowedCommands();

    QCommandLineParser parser;
    parser.setApplicationDescription(QStringLiteral(
        "Glint Studio: change the look, re-render at low spp, navigate or tune filters, paint them "
        "on, compare with a reference (docs/studio.md)."));
    const QCommandLineOption help = parser.addHelpOption();
    const QCommandLineOption version = parser.addVersionOption();
    parser.addPositionalArgument(
        QStringLiteral("file"),
        QStringLiteral(
            "a scene.json, a glTF or OBJ asset, a layered EXR or a .glint-session.json"));
    QCommandLineOption autosave(QStringLiteral("autosave-dir"),
                                QStringLiteral("where edits are journalled (default: the user's "
                                               "application data folder)"),
                                QStringLiteral("DIR"));
    QCommandLineOption noRestore(QStringLiteral("no-restore"),
                                 QStringLiteral("do not offer to restore a crashed session"));
    parser.addOption(autosave);
    parser.addOption(noRestore);
    // Not QCommandLineParser::process, which exits 1 on a bad option: a bad command line exits 2,
    // as every Glint tool does.
    if (!parser.parse(QApplication::arguments())) {
        std::fprintf(stderr, "glint-studio: command line: %s (try --help)\n",
                     qPrintable(parser.errorText()));
        return 2;
    }
    if (parser.isSet(help)) parser.showHelp(0);
    if (parser.isSet(version)) parser.showVersion();
    if (parser.positionalArguments().size() > 1) {
        std::fprintf(stderr, "glint-studio: expected at most one file, got %lld\n",
                     static_cast<long long>(parser.positionalArguments().size()));
        return 2;
    }

    glint::studio::StudioOptions options;
    options.autosaveBase = parser.value(autosave);
    options.offerRestore = !parser.isSet(noRestore);
    glint::studio::MainWindow window(options);
    window.show();
    const QString file = parser.positionalArguments().value(0);
    QTimer::singleShot(0, &window,
                       [&window, &options, file] { window.start(file, options.offerRestore); });
    return app.exec();
}
