#include "views/elided_label.h"

#include <QResizeEvent>

#include <algorithm>

namespace glint::studio {

ElidedLabel::ElidedLabel(QWidget* parent) : QLabel(parent) {
    setTextFormat(Qt::PlainText);
    setWordWrap(false);
}

void ElidedLabel::setFullText(const QString& text) {
    if (text == m_full) return;
    m_full = text;
    elide();
}

QSize ElidedLabel::minimumSizeHint() const {
    return QSize(0, QLabel::minimumSizeHint().height());
}

QSize ElidedLabel::sizeHint() const {
    return QSize(0, QLabel::sizeHint().height());
}

void ElidedLabel::resizeEvent(QResizeEvent* event) {
    QLabel::resizeEvent(event);
    elide();
}

void ElidedLabel::elide() {
    const int room = contentsRect().width() - 2 * margin() - 2 * std::max(0, indent());
    const QString shown = fontMetrics().elidedText(m_full, Qt::ElideRight, std::max(0, room));
    setText(shown);
    setToolTip(shown == m_full ? QString() : m_full);
}

}  // namespace glint::studio
