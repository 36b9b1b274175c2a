// The look panel: the scene's materials, lights and environment with a control per property,
// generated from the scene's LookItems (colours as swatches with numeric fields, scalars as
// sliders, log where the property says so). Each edit is an undo step that re-renders.
#pragma once

#include <QWidget>

#include "model/document.h"
#include "model/session_adapter.h"

class QVBoxLayout;
class QScrollArea;

namespace glint::studio {

class LookPanel : public QWidget {
    Q_OBJECT
  public:
    LookPanel(Document* document, SessionAdapter* session, QWidget* parent = nullptr);

    /// Tall enough to take the larger share of its dock column (Compare sits below it): a few
    /// properties always show.
    QSize sizeHint() const override { return {340, 560}; }
    QSize minimumSizeHint() const override { return {340, 220}; }

    /// Sets a property as the user would (pushes an undo step); for tests and scripts.
    void edit(const std::string& item, const std::string& property,
              const std::array<double, 3>& value);

  signals:
    void failed(const QString& title, const QString& message);

  private:
    void rebuild();
    void refreshValues();
    QWidget* colorControl(const render::LookItem& item, const render::LookProperty& p);
    QWidget* scalarControl(const render::LookItem& item, const render::LookProperty& p);

    Document* m_document;
    SessionAdapter* m_session;
    QWidget* m_content = nullptr;
    QScrollArea* m_scroll;
    std::vector<std::string> m_builtFor;  // item/property keys of the controls
};

}  // namespace glint::studio
