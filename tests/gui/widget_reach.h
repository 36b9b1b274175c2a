// Whether every control of a window can be seen and reached: shared by the laptop-size tests and
// the screenshot tour (which prints what it finds). A control is reachable when it lies inside
// each widget around it, up to the window; inside a scroll area it only has to lie inside the
// scrolled panel (scrolling brings it into view), unless that direction's scroll bar is off.
// Its text must fit too: a label's text (a word-wrapped label's lines) is not cut, a button,
// spin box (with its arrows) or combo box is not narrower than its text needs (an icon button
// has no text to check), and a table's cells and header sections are as wide and tall as their
// text needs (the item delegate's and the header's own size hints). ElidedLabel is the one
// label allowed to shorten its text: it ends it with "…" and shows the whole text in its tooltip
// (the status bar's pixel readout, longer than any screen is wide).
#pragma once

#include <QAbstractButton>
#include <QAbstractItemModel>
#include <QAbstractItemView>
#include <QAbstractScrollArea>
#include <QAbstractSpinBox>
#include <QCheckBox>
#include <QComboBox>
#include <QHeaderView>
#include <QLabel>
#include <QProgressBar>
#include <QRadioButton>
#include <QScrollArea>
#include <QScrollBar>
#include <QSlider>
#include <QStatusBar>
#include <QStringList>
#include <QStyle>
#include <QStyleOptionComboBox>
#include <QStyleOptionSpinBox>
#include <QStyleOptionViewItem>
#include <QTableView>
#include <QToolBar>
#include <QWidget>

#include <algorithm>

#include "views/elided_label.h"

namespace glint::studio::testing {

/// "QPushButton 'Render'" for a failure message.
inline QString describeWidget(const QWidget* w) {
    QString text;
    if (auto* b = qobject_cast<const QAbstractButton*>(w)) text = b->text();
    if (auto* l = qobject_cast<const QLabel*>(w)) text = l->text().left(40);
    if (auto* c = qobject_cast<const QComboBox*>(w)) text = c->currentText();
    if (auto* s = qobject_cast<const QAbstractSpinBox*>(w)) text = s->text();
    QString path;
    for (const QWidget* p = w->parentWidget(); p && !p->isWindow(); p = p->parentWidget())
        if (!p->objectName().isEmpty() && !p->objectName().startsWith(QStringLiteral("qt_"))) {
            path = p->objectName();
            break;
        }
    return QStringLiteral("%1 '%2'%3")
        .arg(QString::fromLatin1(w->metaObject()->className()), text,
             path.isEmpty() ? QString() : QStringLiteral(" in ") + path);
}

/// The controls the walk checks: buttons, spin boxes, combo boxes, sliders, labels, progress
/// bars and the status bar (not the parts of a spin box or combo box, nor scroll bars).
inline bool isCheckedControl(const QWidget* w) {
    const QWidget* parent = w->parentWidget();
    if (parent &&
        (qobject_cast<const QAbstractSpinBox*>(parent) || qobject_cast<const QComboBox*>(parent)))
        return false;
    return qobject_cast<const QAbstractButton*>(w) || qobject_cast<const QAbstractSpinBox*>(w) ||
           qobject_cast<const QComboBox*>(w) || qobject_cast<const QSlider*>(w) ||
           qobject_cast<const QLabel*>(w) || qobject_cast<const QProgressBar*>(w) ||
           qobject_cast<const QStatusBar*>(w);
}

/// Why `w` cannot be reached in its window (empty when it can).
inline QString unreachable(const QWidget* w) {
    const QWidget* window = w->window();
    QRect r = w->geometry();  // in the parent's coordinates
    for (const QWidget* p = w->parentWidget(); p; p = p->parentWidget()) {
        const auto* area = p->parentWidget()
                               ? qobject_cast<const QAbstractScrollArea*>(p->parentWidget())
                               : nullptr;
        if (area && area->viewport() == p) {
            // Scrolled into view when needed; along a direction without a scroll bar it must
            // lie inside the viewport as it is.
            if (area->horizontalScrollBarPolicy() == Qt::ScrollBarAlwaysOff &&
                (r.left() < 0 || r.right() >= p->width()))
                return QStringLiteral(
                           "beyond the right edge of a scroll area without a "
                           "horizontal scroll bar (x %1..%2 of %3)")
                    .arg(r.left())
                    .arg(r.right())
                    .arg(p->width());
            if (area->verticalScrollBarPolicy() == Qt::ScrollBarAlwaysOff &&
                (r.top() < 0 || r.bottom() >= p->height()))
                return QStringLiteral("below a scroll area without a vertical scroll bar");
            r = p->geometry();  // the viewport itself must be reachable
        } else if (!QRect(QPoint(0, 0), p->size()).contains(r)) {
            return QStringLiteral("cut off by %1 (%2,%3 %4×%5 in %6×%7)")
                .arg(QString::fromLatin1(p->metaObject()->className()))
                .arg(r.x())
                .arg(r.y())
                .arg(r.width())
                .arg(r.height())
                .arg(p->width())
                .arg(p->height());
        } else {
            r.translate(p->pos());
        }
        if (p == window) break;
    }
    return {};
}

/// Why the text of `w` does not show whole (empty when it does).
inline QString textCut(const QWidget* w) {
    const QFontMetrics fm(w->font());
    if (qobject_cast<const ElidedLabel*>(w)) return {};  // elides by design, tooltip holds all
    if (auto* label = qobject_cast<const QLabel*>(w)) {
        if (label->text().isEmpty()) return {};
        const QRect room = label->contentsRect();
        if (label->wordWrap()) {
            const int needed = label->heightForWidth(label->width());
            return needed > label->height() ? QStringLiteral("needs %1 px of height, has %2")
                                                  .arg(needed)
                                                  .arg(label->height())
                                            : QString();
        }
        const int needed =
            label->textFormat() == Qt::PlainText ||
                    (label->textFormat() == Qt::AutoText && !Qt::mightBeRichText(label->text()))
                ? fm.horizontalAdvance(label->text()) + 2 * label->margin()
                : label->minimumSizeHint().width();
        return needed > room.width() + 1
                   ? QStringLiteral("text needs %1 px, has %2").arg(needed).arg(room.width())
                   : QString();
    }
    if (auto* combo = qobject_cast<const QComboBox*>(w)) {
        QStyleOptionComboBox option;
        option.initFrom(combo);
        option.editable = combo->isEditable();
        const QSize text(fm.horizontalAdvance(combo->currentText()), fm.height());
        int needed =
            combo->style()->sizeFromContents(QStyle::CT_ComboBox, &option, text, combo).width();
        // A combo box fitted to its items: Qt's own size hint (over all items) is what it needs
        // (this estimate is a pixel or two over it). Else one pixel of slack.
        if (combo->sizeAdjustPolicy() == QComboBox::AdjustToContents)
            needed = std::min(needed, combo->sizeHint().width());
        return needed > combo->width() + 1 ? QStringLiteral("'%1' needs %2 px, has %3")
                                                 .arg(combo->currentText())
                                                 .arg(needed)
                                                 .arg(combo->width())
                                           : QString();
    }
    if (auto* spin = qobject_cast<const QAbstractSpinBox*>(w)) {
        // The text shown and, when it has them, the arrows.
        QStyleOptionSpinBox option;
        option.initFrom(spin);
        option.buttonSymbols = spin->buttonSymbols();
        option.frame = spin->hasFrame();
        option.subControls = QStyle::SC_SpinBoxFrame | QStyle::SC_SpinBoxEditField;
        if (spin->buttonSymbols() != QAbstractSpinBox::NoButtons)
            option.subControls |= QStyle::SC_SpinBoxUp | QStyle::SC_SpinBoxDown;
        const QSize text(fm.horizontalAdvance(spin->text()) + 4, fm.height());
        const int needed =
            spin->style()->sizeFromContents(QStyle::CT_SpinBox, &option, text, spin).width();
        return needed > spin->width() ? QStringLiteral("'%1' needs %2 px, has %3")
                                            .arg(spin->text())
                                            .arg(needed)
                                            .arg(spin->width())
                                      : QString();
    }
    if (auto* button = qobject_cast<const QAbstractButton*>(w)) {
        if (button->text().isEmpty()) return {};  // an icon or a swatch
        // A check box's box and text; a push or tool button's text and a small margin.
        const bool box = qobject_cast<const QCheckBox*>(w) || qobject_cast<const QRadioButton*>(w);
        QString text = button->text();
        text.remove(QLatin1Char('&'));
        // A tool button draws each line of its text on its own (a navigation preview's label
        // is two or three lines): the widest line and all of their heights must fit.
        const QStringList lines = text.split(QLatin1Char('\n'));
        int widest = 0;
        for (const QString& line : lines) widest = std::max(widest, fm.horizontalAdvance(line));
        const int needed = box ? button->minimumSizeHint().width() : widest + 6;
        if (needed > button->width())
            return QStringLiteral("'%1' needs %2 px, has %3")
                .arg(text)
                .arg(needed)
                .arg(button->width());
        const int tall = int(lines.size()) * fm.height();
        return !box && tall > button->height()
                   ? QStringLiteral("'%1' needs %2 px of height, has %3")
                         .arg(text)
                         .arg(tall)
                         .arg(button->height())
                   : QString();
    }
    return {};
}

/// A table's cell or header section for a failure message: "relMSE × Raw image '0.00184'".
inline QString describeCell(const QTableView* table, int row, int column, const QString& text) {
    const QAbstractItemModel* model = table->model();
    const QString rowName = model->headerData(row, Qt::Vertical).toString();
    const QString columnName = model->headerData(column, Qt::Horizontal)
                                   .toString()
                                   .replace(QLatin1Char('\n'), QLatin1Char(' '));
    return QStringLiteral("%1 cell %2 × %3 '%4'")
        .arg(QString::fromLatin1(table->metaObject()->className()),
             rowName.isEmpty() ? QString::number(row) : rowName,
             columnName.isEmpty() ? QString::number(column) : columnName, text);
}

/// Every cell and header section of `table` whose text is elided or cut, one line each: a cell
/// narrower or lower than its item delegate's size hint (the text's width and the delegate's
/// margins), a header section narrower than the header's size hint for it, a header lower than
/// its tallest section's lines, a cell outside the viewport along a direction without a scroll
/// bar.
inline QStringList tableTextCut(const QTableView* table) {
    QStringList problems;
    const QAbstractItemModel* model = table->model();
    if (!model) return problems;
    const QRect viewport = table->viewport()->rect();
    for (int row = 0; row < model->rowCount(table->rootIndex()); ++row) {
        if (table->isRowHidden(row)) continue;
        for (int column = 0; column < model->columnCount(table->rootIndex()); ++column) {
            if (table->isColumnHidden(column)) continue;
            const QModelIndex index = model->index(row, column, table->rootIndex());
            const QString text = index.data(Qt::DisplayRole).toString();
            if (text.isEmpty()) continue;
            const QRect cell = table->visualRect(index);
            QStyleOptionViewItem option;
            option.initFrom(table);
            option.font = table->font();
            option.rect = cell;
            option.textElideMode = table->textElideMode();
            const QSize needed = table->itemDelegateForIndex(index)->sizeHint(option, index);
            const QString where = describeCell(table, row, column, text);
            if (needed.width() > cell.width() || needed.height() > cell.height())
                problems << QStringLiteral("%1: needs %2×%3 px, has %4×%5")
                                .arg(where)
                                .arg(needed.width())
                                .arg(needed.height())
                                .arg(cell.width())
                                .arg(cell.height());
            const bool cutAcross = table->horizontalScrollBarPolicy() == Qt::ScrollBarAlwaysOff &&
                                   (cell.left() < 0 || cell.right() > viewport.right());
            const bool cutDown = table->verticalScrollBarPolicy() == Qt::ScrollBarAlwaysOff &&
                                 (cell.top() < 0 || cell.bottom() > viewport.bottom());
            if (cutAcross || cutDown)
                problems << QStringLiteral("%1: outside the table's %2×%3 view")
                                .arg(where)
                                .arg(viewport.width())
                                .arg(viewport.height());
        }
    }
    for (const QHeaderView* header : {table->horizontalHeader(), table->verticalHeader()}) {
        if (!header->isVisible()) continue;
        const bool across = header->orientation() == Qt::Horizontal;
        for (int section = 0; section < header->count(); ++section) {
            if (header->isSectionHidden(section)) continue;
            const QString text = model->headerData(section, header->orientation()).toString();
            if (text.isEmpty()) continue;
            // Along the header, its size hint for the section; across it, the header's own size
            // hint (its tallest or widest section).
            const int along = header->sectionSize(section);
            const int neededAlong = header->sectionSizeHint(section);
            const int acrossHas = across ? header->height() : header->width();
            const int acrossNeeds =
                across ? header->sizeHint().height() : header->sizeHint().width();
            const QString where =
                QStringLiteral("%1 header '%2'")
                    .arg(across ? QStringLiteral("column") : QStringLiteral("row"),
                         QString(text).replace(QLatin1Char('\n'), QLatin1Char(' ')));
            // A stretched or fitted horizontal section's width, a vertical header's width.
            if (across && neededAlong > along)
                problems << QStringLiteral("%1: needs %2 px, has %3")
                                .arg(where)
                                .arg(neededAlong)
                                .arg(along);
            if (acrossNeeds > acrossHas)
                problems << QStringLiteral("%1: the header needs %2 px %3, has %4")
                                .arg(where)
                                .arg(acrossNeeds)
                                .arg(across ? QStringLiteral("of height")
                                            : QStringLiteral("of width"))
                                .arg(acrossHas);
        }
    }
    return problems;
}

/// Every visible control of `window` that cannot be reached or whose text is cut, one line each;
/// also a tool bar that hides part of itself behind its extension button, and every table cell
/// or header section whose text is cut (tableTextCut).
inline QStringList reachProblems(const QWidget* window) {
    QStringList problems;
    for (const QWidget* w : window->findChildren<QWidget*>()) {
        if (!w->isVisible() || w->window() != window) continue;
        if (w->objectName() == QStringLiteral("qt_toolbar_ext_button")) {
            problems << QStringLiteral("a tool bar is too narrow for its contents");
            continue;
        }
        if (auto* table = qobject_cast<const QTableView*>(w)) problems << tableTextCut(table);
        if (!isCheckedControl(w)) continue;
        for (const QString& why : {unreachable(w), textCut(w)})
            if (!why.isEmpty()) problems << describeWidget(w) + QStringLiteral(": ") + why;
    }
    return problems;
}

}  // namespace glint::studio::testing
