#include "views/help_overlay.h"

#include <QAction>
#include <QEvent>
#include <QPainter>

namespace glint::studio {

HelpOverlay::HelpOverlay(QWidget* parent) : QWidget(parent) {
    hide();
    parent->installEventFilter(this);
}

void HelpOverlay::setActions(const QList<QAction*>& actions) {
    m_actions = actions;
}

void HelpOverlay::toggle() {
    if (isVisible()) {
        hide();
        return;
    }
    setGeometry(parentWidget()->rect());
    raise();
    show();
}

bool HelpOverlay::eventFilter(QObject* watched, QEvent* event) {
    if (watched == parentWidget() && event->type() == QEvent::Resize && isVisible())
        setGeometry(parentWidget()->rect());
    return QWidget::eventFilter(watched, event);
}

void HelpOverlay::mousePressEvent(QMouseEvent*) {
    hide();
}

void HelpOverlay::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), QColor(0, 0, 0, 200));
    p.setPen(Qt::white);
    QFont title = font();
    title.setPointSizeF(title.pointSizeF() * 1.4);
    title.setBold(true);
    p.setFont(title);
    p.drawText(QRect(0, 16, width(), 32), Qt::AlignCenter, tr("Glint Studio — shortcuts"));
    p.setFont(font());
    // Two columns of "shortcut  what it does".
    QStringList lines;
    for (QAction* a : m_actions) {
        if (a->shortcut().isEmpty()) continue;
        QString text = a->text();
        text.remove(QLatin1Char('&'));
        text.remove(QStringLiteral("…"));
        lines << a->shortcut().toString(QKeySequence::NativeText) + QLatin1Char('\t') + text;
    }
    lines << tr("Wheel") + QLatin1Char('\t') + tr("Zoom to the cursor");
    lines << tr("Middle drag") + QLatin1Char('\t') + tr("Pan");
    lines << tr("Shift+drag") + QLatin1Char('\t') + tr("Resize the brush");
    lines << tr("Right button") + QLatin1Char('\t') + tr("Paint out / wand removes");
    lines << tr("Drag the wipe") + QLatin1Char('\t') + tr("Move the A | B split");
    const int rowHeight = fontMetrics().height() + 4;
    const int perColumn = (lines.size() + 1) / 2;
    const int columnWidth = std::min(420, width() / 2 - 40);
    const int left = (width() - 2 * columnWidth) / 2;
    for (int i = 0; i < lines.size(); ++i) {
        const int col = i / perColumn, row = i % perColumn;
        const QStringList parts = lines[i].split(QLatin1Char('\t'));
        const int x = left + col * columnWidth, y = 64 + row * rowHeight;
        p.setPen(QColor(255, 200, 90));
        p.drawText(QRect(x, y, 130, rowHeight), Qt::AlignLeft | Qt::AlignVCenter, parts.value(0));
        p.setPen(Qt::white);
        p.drawText(QRect(x + 136, y, columnWidth - 140, rowHeight),
                   Qt::AlignLeft | Qt::AlignVCenter, parts.value(1));
    }
    p.setPen(QColor(180, 180, 180));
    p.drawText(QRect(0, height() - 32, width(), 24), Qt::AlignCenter,
               tr("F1 or a click closes this sheet · docs/studio.md is the full guide"));
}

}  // namespace glint::studio
