// What `glint-denoise auto` makes of a frame with its defaults, for the tests that hold the
// studio's Auto Start to it (docs/studio.md, "Auto Start"): the frame written to a folder and the
// CLI built beside the test program run on it.
#pragma once

#include <QCoreApplication>
#include <QDir>
#include <QProcess>
#include <QString>

#include <optional>

#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"

namespace glint::studio::testing {

/// The colour of `glint-denoise auto IN --out OUT` (no other flag) on `frame`, written as IN in
/// `folder`; nullopt with `error` set when the command fails.
inline std::optional<Image> cliAutoColour(const FrameBuffers& frame, const QString& folder,
                                          QString& error) {
    QDir().mkpath(folder);
    const QString in = QDir(folder).filePath(QStringLiteral("auto-in.exr"));
    const QString out = QDir(folder).filePath(QStringLiteral("auto-out.exr"));
    writeExr(frame, in.toStdString());
    QProcess cli;
    cli.start(QCoreApplication::applicationDirPath() + QStringLiteral("/glint-denoise"),
              {QStringLiteral("auto"), in, QStringLiteral("--out"), out});
    if (!cli.waitForFinished(600000) || cli.exitStatus() != QProcess::NormalExit ||
        cli.exitCode() != 0) {
        error = QString::fromUtf8(cli.readAllStandardError()) + cli.errorString();
        return std::nullopt;
    }
    return readExr(out.toStdString()).color();
}

}  // namespace glint::studio::testing
