// Every action of the studio with its text, shortcut and tooltip, created in one place; the main
// window connects them. The help overlay lists them.
#pragma once

#include <QAction>
#include <QList>
#include <QObject>

namespace glint::studio {

struct StudioActions {
    QAction* open;
    QAction* openReference;
    QAction* saveSession;
    QAction* saveSessionAs;
    QAction* saveScene;
    QAction* exportExr;
    QAction* exportPng;
    QAction* newSession;
    QAction* recover;
    QAction* quit;
    QAction* undo;
    QAction* redo;
    QAction* render;
    QAction* cancelRender;
    QAction* keepRefining;  ///< checkable: renders go on past their spp (docs/studio.md)
    QAction* fit;
    QAction* oneToOne;
    QAction* flip;
    QAction* wipe;
    QAction* exposureUp;
    QAction* exposureDown;
    std::array<QAction*, 4> stages;
    QAction* lasso;
    QAction* wholeImage;
    QAction* brushSmaller;
    QAction* brushLarger;
    QAction* brush;
    QAction* wand;
    QAction* diffuse;
    QAction* showWeight;
    QAction* autoStart;
    QAction* same;
    QAction* back;
    QAction* help;

    /// All of them, in menu order.
    QList<QAction*> all() const;
};

/// Creates the actions as children of `owner` (the main window, so shortcuts work in it).
StudioActions createActions(QObject* owner);

}  // namespace glint::studio
