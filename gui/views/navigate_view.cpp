#include "views/navigate_view.h"

#include <QCheckBox>
#include <QEvent>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QToolButton>
#include <QVBoxLayout>

#include <algorithm>

#include "glint/denoise/aids.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "model/layer_names.h"
#include "model/learned_member.h"
#include "views/param_controls.h"

namespace glint::studio {

namespace {
constexpr int kThumb = 132;

// The option that shows bank member `pinned` at this level: the option that is that member, else
// the child holding it whose representative is nearest to it; -1 when no option leads to it.
int pinnedOption(const denoise::NavigationTree& tree,
                 const std::vector<denoise::Navigator::Option>& options, int pinned) {
    if (pinned < 0) return -1;
    int best = -1;
    for (int i = 0; i < int(options.size()); ++i) {
        const denoise::Navigator::Option& o = options[std::size_t(i)];
        if (o.member == pinned) return i;
        if (o.node < 0) continue;
        const std::vector<int>& members = tree.node(o.node).members;
        if (std::find(members.begin(), members.end(), pinned) == members.end()) continue;
        if (best < 0 || tree.distance(pinned, o.member) <
                            tree.distance(pinned, options[std::size_t(best)].member))
            best = i;
    }
    return best;
}

}  // namespace

NavigateView::NavigateView(const StudioContext& context, QWidget* parent)
    : StageView(context, parent) {
    m_size = new QSpinBox(this);
    m_size->setRange(4, denoise::kMaxBankSize);
    m_size->setValue(64);
    // The bank's size is the Latin-hypercube samples (as glint-denoise bank --size and Auto
    // Start count it); each filter's defaults join them, so the box says so.
    m_size->setSuffix(tr(" sampled + defaults"));
    m_size->setToolTip(
        tr("Filters sampled over the parameters (Latin hypercube); each filter's default "
           "settings join them, so the bank holds a few more results than this"));
    m_build = new QPushButton(tr("Build bank"), this);
    m_build->setToolTip(tr("Filter the region with every member of the bank (in the background)"));
    m_progress = new QProgressBar(this);
    m_progress->setRange(0, 1000);
    m_progress->setTextVisible(false);
    m_state = new QLabel(this);
    m_state->setWordWrap(true);
    m_grid = new QGridLayout;
    for (int i = 0; i < 4; ++i) {
        auto* b = new QToolButton(this);
        b->setIconSize(QSize(kThumb, kThumb));
        b->setToolButtonStyle(Qt::ToolButtonTextUnderIcon);
        b->setAutoRaise(true);
        b->setObjectName(QStringLiteral("option%1").arg(i));
        b->installEventFilter(this);
        connect(b, &QToolButton::clicked, this, [this, i] { chooseOption(i); });
        m_grid->addWidget(b, i / 2, i % 2);
        m_options.push_back(b);
    }
    m_same = new QPushButton(tr("They look the same"), this);
    m_same->setToolTip(tr("Pick any member below this level (S)"));
    m_back = new QPushButton(tr("Back"), this);
    m_back->setToolTip(tr("Up one level (Backspace)"));
    m_restart = new QPushButton(tr("Restart"), this);
    m_restart->setToolTip(tr("Back to the top of the tree"));
    m_chosen = new QLabel(this);
    m_chosen->setWordWrap(true);
    m_paint = new QPushButton(tr("Paint with it"), this);
    m_apply = new QPushButton(tr("Apply to region"), this);
    m_tune = new QPushButton(tr("Fine-tune"), this);
    m_tune->setToolTip(tr("Open the chosen filter in the tuning view with these parameters"));
    m_variance = new QCheckBox(tr("Show filter variance"), this);
    m_variance->setToolTip(
        tr("Where the bank's results disagree most (bright): where the choice of "
           "filter matters"));

    auto* top = new QHBoxLayout;
    top->addWidget(m_size);
    top->addWidget(m_build);
    auto* nav = new QHBoxLayout;
    nav->addWidget(m_same);
    nav->addWidget(m_back);
    nav->addWidget(m_restart);
    auto* use = new QHBoxLayout;
    use->addWidget(m_paint);
    use->addWidget(m_apply);
    use->addWidget(m_tune);
    auto* layout = new QVBoxLayout(this);
    layout->addLayout(top);
    layout->addWidget(m_progress);
    layout->addWidget(m_state);
    layout->addLayout(m_grid);
    layout->addLayout(nav);
    layout->addWidget(m_chosen);
    layout->addLayout(use);
    layout->addWidget(m_variance);
    layout->addStretch(1);

    connect(m_build, &QPushButton::clicked, this, &NavigateView::build);
    connect(m_same, &QPushButton::clicked, this, &NavigateView::same);
    connect(m_back, &QPushButton::clicked, this, &NavigateView::back);
    connect(m_restart, &QPushButton::clicked, this, &NavigateView::restart);
    connect(m_paint, &QPushButton::clicked, this, [this] { choose(false); });
    connect(m_apply, &QPushButton::clicked, this, [this] { choose(true); });
    connect(m_tune, &QPushButton::clicked, this, [this] {
        if (auto m = chosen()) emit tuneRequested(m->filter, m->params);
    });
    connect(m_variance, &QCheckBox::toggled, this, &NavigateView::updateOverlay);
    showOptions();
}

void NavigateView::activate() {
    m_context.viewer->canvas()->setTool(ImageCanvas::Tool::Pan);
    FramePtr in = m_context.session->input();
    // A bank of another render or region is stale: build again.
    if (in &&
        (in != m_builtFor || m_context.region->bounds(in->width(), in->height()) != m_builtRect))
        build();
    updateOverlay();
}

void NavigateView::deactivate() {
    m_context.viewer->canvas()->clearPreview();
    m_context.viewer->canvas()->clearOverlay();
}

void NavigateView::build() {
    FramePtr in = m_context.session->input();
    if (!in) return;
    const Rect rect = m_context.region->bounds(in->width(), in->height());
    // The studio's bank (Auto Start's too): with the learned filter when it runs here, and the
    // filters and fixed parameters of the bank folder the session names.
    const denoise::BankOptions options = m_context.session->bankOptions(m_size->value(), rect);
    denoise::TreeOptions tree;
    tree.exposure = float(m_context.viewer->exposure());
    m_navigator.reset();
    m_bank.reset();
    m_tree.reset();
    m_learned = -1;
    m_builtFor = in;
    m_builtRect = rect;
    m_builtSize = options.size;
    showOptions();
    m_progress->setValue(0);
    m_state->setText(tr("Building a bank over %1×%2 pixels: %3 sampled filters and each "
                        "filter's defaults…")
                         .arg(rect.width())
                         .arg(rect.height())
                         .arg(options.size));
    // The bank from the studio's bank service (Auto Start may have built it already), then its
    // tree on a worker.
    BankService* banks = m_context.session->banks();
    banks->withdraw(m_bankTicket);
    m_tasks.cancel(QStringLiteral("tree"));
    m_bankTicket = banks->request(in, options, this,
                                  {[this, tree](BankService::BankPtr bank) {
                                       m_bankTicket = 0;
                                       buildTree(std::move(bank), tree);
                                   },
                                   [this](double f) { m_progress->setValue(int(f * 900.0)); },
                                   [this](const QString& message) {
                                       m_bankTicket = 0;
                                       m_state->setText(message);
                                       emit failed(tr("Cannot build the bank"), message);
                                   }});
}

void NavigateView::buildTree(std::shared_ptr<const denoise::FilterBank> bank,
                             const denoise::TreeOptions& tree) {
    m_tasks.run<std::shared_ptr<const denoise::NavigationTree>>(
        QStringLiteral("tree"),
        [bank, tree](const TaskRunner::CancelFlag&) {
            return std::make_shared<const denoise::NavigationTree>(
                denoise::NavigationTree::fromBank(*bank, tree));
        },
        [this, bank](std::shared_ptr<const denoise::NavigationTree> t) {
            m_bank = bank;
            m_tree = t;
            m_learned = -1;
            for (std::size_t i = 0; i < bank->size() && m_learned < 0; ++i)
                if (bank->members()[i].filter == kLearnedFilter) m_learned = int(i);
            m_navigator = std::make_unique<denoise::Navigator>(*m_tree);
            m_progress->setValue(1000);
            m_state->setText(bankText(*m_bank, m_builtSize, *m_builtFor));
            showOptions();
            updateOverlay();
            emit bankReady();
        },
        [this](const QString& message) {
            m_state->setText(message);
            emit failed(tr("Cannot build the bank"), message);
        });
}

void NavigateView::setBankSize(int size) {
    m_size->setValue(size);
}

int NavigateView::optionCount() const {
    return int(m_shownMembers.size());
}

int NavigateView::depth() const {
    return m_navigator ? m_navigator->choices() : 0;
}

std::optional<denoise::BankMember> NavigateView::chosen() const {
    if (!m_navigator || !m_navigator->chosen()) return std::nullopt;
    return m_bank->members()[std::size_t(*m_navigator->chosen())];
}

QString NavigateView::bankText(const denoise::FilterBank& bank, int sampled,
                               const FrameBuffers& input) {
    const auto defaults = std::count_if(bank.members().begin(), bank.members().end(),
                                        [](const denoise::BankMember& m) { return m.isDefault; });
    const qsizetype kept = qsizetype(bank.size()) - defaults;
    QString text = tr("%1 filter results: %2 sampled and the defaults of %3 filters")
                       .arg(bank.size())
                       .arg(kept)
                       .arg(defaults);
    if (kept < sampled) {
        // Why samples are missing: a filter whose parameters are all fixed (unet, external) is
        // its default only, and members needing a layer the image lacks are left out.
        QStringList fixed;
        for (const denoise::BankMember& m : bank.members()) {
            const auto& specs = denoise::findFilter(m.filter).params();
            if (m.isDefault && std::all_of(specs.begin(), specs.end(), [](const auto& spec) {
                    return spec.softMin == spec.softMax;
                }))
                fixed << QString::fromStdString(m.filter);
        }
        QStringList why;
        if (!fixed.isEmpty())
            why << tr("fixed parameters (%1) have their default only")
                       .arg(fixed.join(QStringLiteral(", ")));
        if (!input.has(Layer::Albedo) || !input.has(Layer::Normal) || !input.has(Layer::Depth))
            why << tr("some need layers this image lacks");
        text += tr(" (%1 of the %2 sampled left out: %3)")
                    .arg(sampled - kept)
                    .arg(sampled)
                    .arg(why.join(tr("; ")));
    }
    return text + tr("; pick the one you like best.");
}

void NavigateView::showOptions() {
    m_shownMembers.clear();
    const bool done = m_navigator && m_navigator->chosen();
    std::vector<denoise::Navigator::Option> options;
    if (m_navigator && !done) options = m_navigator->options();
    // The learned result is pinned: whichever option leads to it shows it.
    m_learnedOption = m_tree ? pinnedOption(*m_tree, options, m_learned) : -1;
    std::vector<OptionMember> shown;
    std::vector<const Image*> images;
    for (std::size_t i = 0; i < options.size() && i < m_options.size(); ++i) {
        const int member = int(i) == m_learnedOption ? m_learned : options[i].member;
        const denoise::BankMember& m = m_bank->members()[std::size_t(member)];
        m_shownMembers.push_back(member);
        shown.push_back({m.filter, m.params});
        images.push_back(&m_bank->result(std::size_t(member)));
    }
    // Each preview says what sets it apart from the others (docs/studio.md, "Navigate").
    const std::vector<QStringList> labels = distinguishingLabels(shown);
    m_contrast = contrastOf(images);
    // The thumbnails show the part of the region where the options differ most (at half
    // scale), not the whole region shrunk until they look alike.
    const Rect window = mostDifferentWindow(images, 2 * kThumb);
    const bool cropped = !images.empty() && (window.width() < images.front()->width() ||
                                             window.height() < images.front()->height());
    const DisplaySettings display = m_context.viewer->canvas()->display();
    for (std::size_t i = 0; i < m_options.size(); ++i) {
        QToolButton* b = m_options[i];
        if (i < m_shownMembers.size()) {
            const QImage image = toQImage(cropped ? images[i]->crop(window) : *images[i], display);
            b->setIcon(QIcon(QPixmap::fromImage(
                image.scaled(kThumb, kThumb, Qt::KeepAspectRatio, Qt::SmoothTransformation))));
            QStringList lines = labels[i];
            if (!m_contrast.words[i].isEmpty()) lines << m_contrast.words[i];
            b->setText(lines.join(QLatin1Char('\n')));
            QString tip = layerParameters(shown[i].filter, shown[i].params);
            if (options[i].node >= 0)
                tip += tr("\n%1 results alike below it")
                           .arg(m_tree->node(options[i].node).members.size());
            if (int(i) == m_learnedOption) tip += tr("\nThe learned result (pinned)");
            b->setToolTip(tip);
            b->setEnabled(true);
            b->setVisible(true);
        } else {
            b->setIcon(QIcon());
            b->setText(QString());
            b->setEnabled(false);
            b->setVisible(i < 4 && !done);
        }
    }
    m_same->setEnabled(m_navigator && !done);
    m_back->setEnabled(m_navigator && m_navigator->choices() > 0);
    m_restart->setEnabled(m_navigator && m_navigator->choices() > 0);
    m_paint->setEnabled(done);
    m_apply->setEnabled(done);
    m_tune->setEnabled(done);
    if (done) {
        // The choice in user terms; every parameter in the tooltip.
        const denoise::BankMember& m = m_bank->members()[std::size_t(*m_navigator->chosen())];
        m_chosen->setText(tr("Chosen: %1").arg(choiceName(m.filter, m.params)));
        m_chosen->setToolTip(layerParameters(m.filter, m.params));
        showMember(*m_navigator->chosen());
    } else {
        QString text;
        if (m_navigator) {
            text = (cropped ? tr("Level %1: the previews show where they differ most; hover one "
                                 "to see it on the image, click the best.")
                            : tr("Level %1: hover a preview to see it on the image, click the "
                                 "best."))
                       .arg(m_navigator->choices() + 1);
            if (m_contrast.nearIdentical && m_shownMembers.size() > 1)
                text = tr("Level %1: these %2 previews are near-identical (they differ by "
                          "%3 % at most): pick any, or They look the same (S).")
                           .arg(m_navigator->choices() + 1)
                           .arg(m_shownMembers.size())
                           .arg(std::max(m_contrast.maxDifference * 100.0, 0.01), 0, 'g', 2);
        }
        m_chosen->setText(text);
        m_chosen->setToolTip(QString());
        m_context.viewer->canvas()->clearPreview();
    }
}

QString NavigateView::optionText(int i) const {
    return i >= 0 && i < int(m_options.size()) ? m_options[std::size_t(i)]->text() : QString();
}

QString NavigateView::stateText() const {
    return m_chosen->text();
}

void NavigateView::showMember(int member) {
    if (!m_bank || !m_active) return;
    m_context.viewer->canvas()->setPreview(m_bank->result(std::size_t(member)), m_bank->region());
}

void NavigateView::chooseOption(int i) {
    if (!m_navigator || i < 0 || i >= optionCount()) return;
    m_navigator->choose(i);
    showOptions();
}

void NavigateView::hoverOption(int i) {
    if (i >= 0 && i < optionCount()) showMember(m_shownMembers[std::size_t(i)]);
}

void NavigateView::same() {
    if (!m_navigator) return;
    m_navigator->same();
    showOptions();
}

void NavigateView::back() {
    if (!m_navigator) return;
    m_navigator->back();
    showOptions();
}

void NavigateView::restart() {
    if (!m_navigator) return;
    m_navigator->restart();
    showOptions();
}

void NavigateView::choose(bool fillRegion) {
    const std::optional<denoise::BankMember> m = chosen();
    if (!m) return;
    try {
        addChosenLayer(m_context, m->filter, m->params, fillRegion);
        emit layerChosen();
    } catch (const Error& e) {
        emit failed(tr("Cannot add the layer"), QString::fromStdString(e.what()));
    }
}

bool NavigateView::eventFilter(QObject* watched, QEvent* event) {
    for (std::size_t i = 0; i < m_options.size(); ++i) {
        if (watched != m_options[i]) continue;
        if (event->type() == QEvent::Enter) hoverOption(int(i));
        if (event->type() == QEvent::Leave) {
            if (m_navigator && m_navigator->chosen())
                showMember(*m_navigator->chosen());
            else
                m_context.viewer->canvas()->clearPreview();
        }
    }
    return StageView::eventFilter(watched, event);
}

void NavigateView::updateOverlay() {
    ImageCanvas* canvas = m_context.viewer->canvas();
    FramePtr in = m_context.session->input();
    if (!m_active || !m_variance->isChecked() || !m_bank || !in) {
        m_tasks.cancel(QStringLiteral("variance"));
        canvas->clearOverlay();
        return;
    }
    // The variance of the bank's results (tens of megapixels to read), on a worker.
    std::shared_ptr<const denoise::FilterBank> bank = m_bank;
    const int width = in->width(), height = in->height();
    m_tasks.run<QImage>(
        QStringLiteral("variance"),
        [bank, width, height](const TaskRunner::CancelFlag&) {
            std::vector<const Image*> results;
            for (const Image& r : bank->results()) results.push_back(&r);
            const Image variance = denoise::filterVarianceMap(results);
            // Placed over the region in a frame-sized overlay.
            Image full(width, height, 1, 0.0f);
            const Rect r = bank->region();
            for (int y = r.y0; y < r.y1; ++y)
                for (int x = r.x0; x < r.x1; ++x) full(x, y, 0) = variance(x - r.x0, y - r.y0, 0);
            return maskOverlay(full, QColor(255, 60, 200, 200));
        },
        [this, bank](QImage overlay) {
            if (m_active && m_variance->isChecked() && m_bank == bank)
                m_context.viewer->canvas()->setOverlay(overlay);
        });
}

}  // namespace glint::studio
