// A one-line label that shows as much of its text as fits and ends it with "…" (the whole text
// in its tooltip), instead of cutting a character in half at its right edge. The status bar's
// pixel readout is one: it lists more layers than a laptop screen is wide.
#pragma once

#include <QLabel>
#include <QString>

namespace glint::studio {

class ElidedLabel : public QLabel {
    Q_OBJECT
  public:
    explicit ElidedLabel(QWidget* parent = nullptr);
    /// Sets the whole text; the label shows what fits of it.
    void setFullText(const QString& text);
    const QString& fullText() const { return m_full; }
    /// The label asks for no width of its own: the window's width decides what shows.
    QSize minimumSizeHint() const override;
    QSize sizeHint() const override;

  protected:
    void resizeEvent(QResizeEvent* event) override;

  private:
    void elide();

    QString m_full;
};

}  // namespace glint::studio
