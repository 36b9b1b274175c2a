// Stage 3 by navigation: a filter bank over the region, built in the background with progress,
// organised as a soft clustering tree; the four previews of the current level (hover one to see
// it large on the image, click to descend), "They look the same", back and restart; the filter
// variance of the bank as a visual aid. The learned filter's result, when the bank holds it, is
// pinned: the option whose subtree holds it shows it instead of its representative, down to the
// leaf where it can be picked (docs/navigation.md, "The learned member").
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "model/bank_service.h"
#include "model/option_labels.h"
#include "model/task_runner.h"
#include "views/stage_view.h"

class QGridLayout;
class QLabel;
class QProgressBar;
class QPushButton;
class QSpinBox;
class QToolButton;
class QCheckBox;

namespace glint::studio {

class NavigateView : public StageView {
    Q_OBJECT
  public:
    NavigateView(const StudioContext& context, QWidget* parent = nullptr);

    /// Builds the bank and its tree over the region (in the background).
    void build();
    /// Latin-hypercube members of the next bank (each filter's defaults join them).
    void setBankSize(int size);
    bool ready() const { return m_navigator != nullptr; }
    /// The options shown now (their number; 0 before the bank is built).
    int optionCount() const;
    /// Descends into option i (as a click would), hovers it (as the mouse would), or the others.
    void chooseOption(int i);
    void hoverOption(int i);
    void same();
    void back();
    void restart();
    /// Levels descended so far (a pick counts).
    int depth() const;
    /// The member picked, once done.
    std::optional<denoise::BankMember> chosen() const;
    /// The option that shows the learned filter's result (pinned: see showOptions), or -1 when
    /// this level holds none (or the bank has no learned member).
    int learnedOption() const { return m_learnedOption; }
    /// The text of option i's preview (what sets it apart from the others shown) and of the
    /// line under the previews (the level, near-identical options, or the choice).
    QString optionText(int i) const;
    QString stateText() const;
    /// How the options shown now differ (their detail, whether they are near-identical).
    const OptionContrast& contrast() const { return m_contrast; }
    /// Adds the chosen member as a layer.
    void choose(bool fillRegion);

  signals:
    void bankReady();
    /// The user asks to fine-tune the chosen member's parameters.
    void tuneRequested(const std::string& filter, const denoise::ParamValues& params);

  protected:
    void activate() override;
    void deactivate() override;
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    void buildTree(std::shared_ptr<const denoise::FilterBank> bank,
                   const denoise::TreeOptions& tree);
    void showOptions();
    void showMember(int member);
    void updateOverlay();
    // What the bank holds: its results, how many were sampled and how many are defaults, and
    // why sampled members are missing (on `input`, the frame it was built on).
    static QString bankText(const denoise::FilterBank& bank, int sampled,
                            const FrameBuffers& input);

    TaskRunner m_tasks;
    QSpinBox* m_size;
    QPushButton* m_build;
    QProgressBar* m_progress;
    QLabel* m_state;
    QGridLayout* m_grid;
    std::vector<QToolButton*> m_options;
    QPushButton* m_same;
    QPushButton* m_back;
    QPushButton* m_restart;
    QLabel* m_chosen;
    QPushButton* m_paint;
    QPushButton* m_apply;
    QPushButton* m_tune;
    QCheckBox* m_variance;

    std::shared_ptr<const denoise::FilterBank> m_bank;
    std::shared_ptr<const denoise::NavigationTree> m_tree;
    std::unique_ptr<denoise::Navigator> m_navigator;
    std::vector<int> m_shownMembers;  // member of each option button
    OptionContrast m_contrast;        // of the options shown
    int m_learned = -1;               // the bank's learned member (unet), or -1
    int m_learnedOption = -1;         // the option showing it now, or -1
    FramePtr m_builtFor;              // the input the bank was built on
    Rect m_builtRect{};
    int m_builtSize = 0;                   // the Latin-hypercube samples asked of it
    BankService::Ticket m_bankTicket = 0;  // the bank asked of the bank service
};

}  // namespace glint::studio
