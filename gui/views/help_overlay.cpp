#include "views/help_overlay.h"

#include <QAction>
#include <QEvent>
#include <QPainter>

#include <algorithm>

namespace glint::studio {

namespace {
constexpr int kMargin = 16;     // between the window's edge and the sheet
constexpr int kPadding = 20;    // inside the sheet
constexpr int kKeyGap = 14;     // between a key and its text
constexpr int kColumnGap = 36;  // between columns
constexpr int kRowSpacing = 4;
constexpr int kOneColumnRows = 16;  // more rows than this go in two columns when they fit
const QColor kCard(28, 28, 32);
}  // namespace

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

std::vector<std::pair<QString, QString>> HelpOverlay::lines() const {
    std::vector<std::pair<QString, QString>> lines;
    for (QAction* a : m_actions) {
        if (a->shortcut().isEmpty()) continue;
        QString text = a->text();
        text.remove(QLatin1Char('&'));
        text.remove(QStringLiteral("…"));
        lines.emplace_back(a->shortcut().toString(QKeySequence::NativeText), text);
    }
    lines.emplace_back(tr("Wheel"), tr("Zoom to the cursor"));
    lines.emplace_back(tr("Middle drag"), tr("Pan"));
    lines.emplace_back(tr("Shift+drag"), tr("Resize the brush"));
    lines.emplace_back(tr("Right button"), tr("Paint out / wand removes"));
    lines.emplace_back(tr("Drag the wipe"), tr("Move the A | B split"));
    return lines;
}

QString HelpOverlay::titleText() const {
    return tr("Glint Studio — shortcuts");
}

QString HelpOverlay::footerText() const {
    return tr("F1 or a click closes this sheet · docs/studio.md is the full guide");
}

QFont HelpOverlay::titleFont() const {
    QFont title = font();
    title.setPointSizeF(title.pointSizeF() * 1.4);
    title.setBold(true);
    return title;
}

HelpOverlay::Sheet HelpOverlay::layoutFor(QSize size) const {
    Sheet sheet;
    const std::vector<std::pair<QString, QString>> all = lines();
    const QFontMetrics fm = fontMetrics();
    const int titleHeight = QFontMetrics(titleFont()).height() + 12;
    const int footerHeight = fm.height() + 12;
    const int rowHeight = fm.height() + kRowSpacing;
    // 1. Columns: as few as the window's height allows, the rows balanced between them.
    const int maxCard = std::max(0, size.height() - 2 * kMargin);
    const int rowsRoom = maxCard - 2 * kPadding - titleHeight - footerHeight;
    const int fitting = std::max(1, rowsRoom / rowHeight);
    const int n = int(all.size());
    sheet.columns = std::max(1, (n + fitting - 1) / fitting);
    // 2. Widths from the texts, shrunk (texts elided) only when the window is too narrow.
    int keyWidth = 0, textWidth = 0;
    for (const auto& [key, text] : all) {
        keyWidth = std::max(keyWidth, fm.horizontalAdvance(key));
        textWidth = std::max(textWidth, fm.horizontalAdvance(text));
    }
    const int roomWidth = size.width() - 2 * kMargin - 2 * kPadding;
    // A long list reads better in two columns than in one tall one, when they fit.
    if (sheet.columns == 1 && n > kOneColumnRows &&
        2 * (keyWidth + kKeyGap + textWidth) + kColumnGap <= roomWidth)
        sheet.columns = 2;
    const int perColumn = std::max(1, (n + sheet.columns - 1) / sheet.columns);
    const int columnRoom = (roomWidth - (sheet.columns - 1) * kColumnGap) / sheet.columns;
    if (keyWidth + kKeyGap + textWidth > columnRoom) {
        keyWidth = std::min(keyWidth, std::max(1, columnRoom / 3));
        textWidth = std::max(1, columnRoom - keyWidth - kKeyGap);
    }
    const int columnWidth = keyWidth + kKeyGap + textWidth;
    const int rowsWidth = sheet.columns * columnWidth + (sheet.columns - 1) * kColumnGap;
    const int titleWidth = QFontMetrics(titleFont()).horizontalAdvance(titleText());
    const int footerWidth = fm.horizontalAdvance(footerText());
    const int innerWidth =
        std::min(std::max({rowsWidth, titleWidth, footerWidth}), std::max(1, roomWidth));
    const int cardHeight = std::min(
        maxCard, 2 * kPadding + titleHeight + footerHeight + std::min(perColumn, n) * rowHeight);
    // 3. The sheet, centred; the rows centred in it.
    sheet.card = QRect((size.width() - innerWidth) / 2 - kPadding, (size.height() - cardHeight) / 2,
                       innerWidth + 2 * kPadding, cardHeight);
    const int left =
        sheet.card.left() + kPadding + (innerWidth - std::min(rowsWidth, innerWidth)) / 2;
    const int top = sheet.card.top() + kPadding + titleHeight;
    sheet.title =
        QRect(sheet.card.left(), sheet.card.top() + kPadding, sheet.card.width(), titleHeight - 12);
    sheet.footer = QRect(sheet.card.left(), sheet.card.bottom() + 1 - kPadding - fm.height(),
                         sheet.card.width(), fm.height());
    for (int i = 0; i < n; ++i) {
        const int col = i / perColumn, row = i % perColumn;
        const int x = left + col * (columnWidth + kColumnGap), y = top + row * rowHeight;
        sheet.rows.push_back({all[std::size_t(i)].first, all[std::size_t(i)].second,
                              QRect(x, y, keyWidth, rowHeight),
                              QRect(x + keyWidth + kKeyGap, y, textWidth, rowHeight)});
    }
    return sheet;
}

void HelpOverlay::paintEvent(QPaintEvent*) {
    const Sheet sheet = layoutFor(size());
    QPainter p(this);
    // The window dimmed, and the sheet opaque over it: nothing underneath shows through the text.
    p.fillRect(rect(), QColor(0, 0, 0, 150));
    p.setPen(QColor(90, 90, 100));
    p.setBrush(kCard);
    p.drawRect(sheet.card.adjusted(0, 0, -1, -1));
    p.setFont(titleFont());
    p.setPen(Qt::white);
    p.drawText(sheet.title, Qt::AlignCenter, titleText());
    p.setFont(font());
    const QFontMetrics fm = fontMetrics();
    p.setClipRect(sheet.card.adjusted(1, 1, -1, -kPadding - fm.height()));
    for (const Row& row : sheet.rows) {
        p.setPen(QColor(255, 200, 90));
        p.drawText(row.keyRect, Qt::AlignLeft | Qt::AlignVCenter,
                   fm.elidedText(row.key, Qt::ElideRight, row.keyRect.width()));
        p.setPen(Qt::white);
        p.drawText(row.textRect, Qt::AlignLeft | Qt::AlignVCenter,
                   fm.elidedText(row.text, Qt::ElideRight, row.textRect.width()));
    }
    p.setClipping(false);
    p.setPen(QColor(180, 180, 180));
    p.drawText(sheet.footer, Qt::AlignCenter,
               fm.elidedText(footerText(), Qt::ElideRight, sheet.footer.width()));
}

}  // namespace glint::studio
