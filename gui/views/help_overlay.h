// The shortcut overlay (F1): the window dimmed, and over it an opaque sheet listing every action
// that has a shortcut, generated from the actions themselves so it never goes stale. The sheet is
// laid out from the texts' widths: as many balanced columns as the window's height needs, centred
// and inside the window (texts are elided only when even that does not fit).
#pragma once

#include <QList>
#include <QRect>
#include <QString>
#include <QWidget>

#include <vector>

class QAction;

namespace glint::studio {

class HelpOverlay : public QWidget {
    Q_OBJECT
  public:
    /// One line of the sheet: the key and what it does, and where each is drawn.
    struct Row {
        QString key, text;
        QRect keyRect, textRect;
    };
    /// Where everything is drawn in an overlay of a given size.
    struct Sheet {
        QRect card;  ///< the opaque sheet
        QRect title, footer;
        int columns = 0;
        std::vector<Row> rows;
    };

    explicit HelpOverlay(QWidget* parent);
    /// The actions to list (those with a shortcut), in order.
    void setActions(const QList<QAction*>& actions);
    /// Shows the overlay over the whole parent, or hides it.
    void toggle();
    /// The sheet's layout in an overlay of `size` (the overlay's own size when drawn).
    Sheet layoutFor(QSize size) const;

  protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    // The (key, what it does) lines: the actions' shortcuts, then the mouse's gestures.
    std::vector<std::pair<QString, QString>> lines() const;
    QFont titleFont() const;
    QString titleText() const;
    QString footerText() const;

    QList<QAction*> m_actions;
};

}  // namespace glint::studio
