// glint-studio [SCENE.json | IMAGE.exr | SESSION.glint-session.json]
#include <QApplication>
#include <QCommandLineParser>
#include <QStringList>
#include <QTimer>

#include <cstdio>
#include <exception>

#include "app/main_window.h"
#include "app/openmp_policy.h"
#include "app/studio_settings.h"
#include "glint/image/error.h"
#include "glint/image/tev_client.h"
#include "glint/render/asset_formats.h"

int main(int argc, char** argv) {
    // OpenMP's passive wait for the learned layer's network, unless the user chose a policy: the
    // studio runs itself again with it set (docs/lab/keep-refining.md).
    glint::studio::usePassiveOpenMpWait(argv);
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
    QStringList formats;
    for (const auto& format : glint::render::assetFormats())
        formats << QString::fromStdString(format.name);
    parser.addPositionalArgument(
        QStringLiteral("file"),
        QStringLiteral("a scene.json, an asset (%1), a layered EXR or a .glint-session.json")
            .arg(formats.join(QStringLiteral(", "))));
    QCommandLineOption autosave(QStringLiteral("autosave-dir"),
                                QStringLiteral("where edits are journalled (default: the user's "
                                               "application data folder)"),
                                QStringLiteral("DIR"));
    QCommandLineOption noRestore(QStringLiteral("no-restore"),
                                 QStringLiteral("do not offer to restore a crashed session"));
    QCommandLineOption tevListen(
        QStringLiteral("tev-listen"),
        QStringLiteral("listen on this port of 127.0.0.1 for images sent by tev clients "
                       "(pbrt-v4 --display-server, glint-render --display); 14158 is tev's own"),
        QStringLiteral("PORT"));
    QCommandLineOption tevDisplay(
        QStringLiteral("tev-display"),
        QStringLiteral("send each pass of the studio's renders to tev at HOST:PORT"),
        QStringLiteral("HOST:PORT"));
    parser.addOption(autosave);
    parser.addOption(noRestore);
    parser.addOption(tevListen);
    parser.addOption(tevDisplay);
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
    // tev: the settings, then the command line (docs/studio.md, "Receiving images").
    const glint::studio::TevSettings tev = glint::studio::tevSettings();
    options.tevListenPort = tev.listenPort;
    options.tevAnyInterface = tev.anyInterface;
    options.tevDisplay = tev.display;
    if (parser.isSet(tevListen)) {
        bool ok = false;
        options.tevListenPort = parser.value(tevListen).toInt(&ok);
        if (!ok || options.tevListenPort < 0 || options.tevListenPort > 65535) {
            std::fprintf(stderr,
                         "glint-studio: command line: --tev-listen: '%s' is no port "
                         "(expected 0 … 65535)\n",
                         qPrintable(parser.value(tevListen)));
            return 2;
        }
    }
    if (parser.isSet(tevDisplay)) {
        options.tevDisplay = parser.value(tevDisplay);
        try {
            glint::tev::parseAddress(options.tevDisplay.toStdString(), "--tev-display");
        } catch (const glint::Error& e) {
            std::fprintf(stderr, "glint-studio: %s\n", glint::oneLine(e.what()).c_str());
            return 2;
        }
    }
    glint::studio::MainWindow window(options);
    window.show();
    const QString file = parser.positionalArguments().value(0);
    QTimer::singleShot(0, &window,
                       [&window, &options, file] { window.start(file, options.offerRestore); });
    return app.exec();
}
