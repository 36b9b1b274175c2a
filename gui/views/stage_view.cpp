#include "views/stage_view.h"

#include <QAbstractButton>
#include <QButtonGroup>

namespace glint::studio {

StageView::StageView(const StudioContext& context, QWidget* parent)
    : QWidget(parent), m_context(context) {
    // The canvas's tool changed (a shortcut, another panel): the buttons show it.
    connect(m_context.viewer->canvas(), &ImageCanvas::toolChanged, this,
            [this](ImageCanvas::Tool tool) {
                if (!m_active || !m_tools) return;
                if (QAbstractButton* b = m_tools->button(int(tool)); b && !b->isChecked())
                    b->setChecked(true);
            });
}

void StageView::addToolButton(QAbstractButton* button, ImageCanvas::Tool tool) {
    if (!m_tools) {
        m_tools = new QButtonGroup(this);
        m_tools->setExclusive(true);
        connect(m_tools, &QButtonGroup::idToggled, this, [this](int id, bool on) {
            if (on && m_active) m_context.viewer->canvas()->setTool(ImageCanvas::Tool(id));
        });
    }
    button->setCheckable(true);
    m_tools->addButton(button, int(tool));
}

ImageCanvas::Tool StageView::tool() const {
    if (!m_tools || m_tools->checkedId() < 0) return ImageCanvas::Tool::Pan;
    return ImageCanvas::Tool(m_tools->checkedId());
}

void StageView::selectTool(ImageCanvas::Tool tool) {
    if (!m_tools) return;
    if (QAbstractButton* b = m_tools->button(int(tool))) b->setChecked(true);
    if (m_active) applyTool();
}

void StageView::applyTool() {
    m_context.viewer->canvas()->setTool(tool());
}

}  // namespace glint::studio
