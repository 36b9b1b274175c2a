#include "views/paint_view.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QRegularExpression>
#include <QSignalBlocker>
#include <QSlider>
#include <QToolButton>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

#include "glint/denoise/aids.h"
#include "glint/denoise/registry.h"
#include "model/blocked_programs.h"
#include "model/layer_names.h"
#include "views/param_controls.h"

namespace glint::studio {

namespace {

QString layerText(const denoise::SessionLayer& layer, std::size_t index,
                  const SessionAdapter::AutoChoiceMap* autoChoice) {
    QString name = layer.name.empty() ? layerName(layer.filter, layer.params)
                                      : QString::fromStdString(layer.name);
    if (autoChoice && layer.name.empty())
        name = QObject::tr("Auto result (%n member(s))", "", autoChoice->used);
    return QStringLiteral("%1. %2").arg(index + 1).arg(name);
}

// The choice map as an image, each member in its colour (the members covering most pixels
// first), and its legend: the largest members by name, the rest counted.
struct ChoiceOverlay {
    QImage image;
    QList<QPair<QColor, QString>> legend;
};

ChoiceOverlay choiceOverlay(const SessionAdapter::AutoChoiceMap& map) {
    constexpr int kNamed = 6;
    const Image& choice = *map.choice;
    const int members = int(map.members.size());
    std::vector<std::size_t> count(std::size_t(members) + 1, 0);
    auto memberAt = [&](int x, int y) {
        const int m = int(choice(x, y, 0));
        return m >= 0 && m < members ? m : members;
    };
    for (int y = 0; y < choice.height(); ++y)
        for (int x = 0; x < choice.width(); ++x) ++count[std::size_t(memberAt(x, y))];
    std::vector<int> order(static_cast<std::size_t>(members));
    for (int i = 0; i < members; ++i) order[std::size_t(i)] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return count[std::size_t(a)] > count[std::size_t(b)]; });
    std::vector<QColor> colour(std::size_t(members) + 1, QColor(128, 128, 128));
    ChoiceOverlay out;
    int others = 0;
    for (int rank = 0; rank < members; ++rank) {
        const int m = order[std::size_t(rank)];
        if (count[std::size_t(m)] == 0) break;
        colour[std::size_t(m)] = rank < kNamed ? categoryColor(rank) : QColor(128, 128, 128);
        const double share = 100.0 * double(count[std::size_t(m)]) /
                             double(std::size_t(choice.width()) * std::size_t(choice.height()));
        if (rank < kNamed)
            out.legend << qMakePair(colour[std::size_t(m)],
                                    QStringLiteral("%1 · %2 %")
                                        .arg(map.members[m])
                                        .arg(share, 0, 'f', share < 1.0 ? 1 : 0));
        else
            ++others;
    }
    if (others > 0)
        out.legend << qMakePair(QColor(128, 128, 128),
                                QObject::tr("%n other member(s)", "", others));
    out.image = QImage(choice.width(), choice.height(), QImage::Format_ARGB32_Premultiplied);
    for (int y = 0; y < choice.height(); ++y) {
        auto* dst = reinterpret_cast<QRgb*>(out.image.scanLine(y));
        for (int x = 0; x < choice.width(); ++x) {
            const QColor& c = colour[std::size_t(memberAt(x, y))];
            dst[x] = qPremultiply(qRgba(c.red(), c.green(), c.blue(), 190));
        }
    }
    return out;
}

// The name typed into row `index` ("3. walls" or "walls"): "" when it is the filter's own name.
std::string typedName(const QString& text, const denoise::SessionLayer& layer) {
    QString name = text.trimmed();
    static const QRegularExpression number(QStringLiteral("^\\d+\\.\\s*"));
    static const QRegularExpression unavailable(QStringLiteral("\\s*\\(unavailable\\)$"));
    name.remove(number);
    name.remove(unavailable);
    if (name.isEmpty() || name == layerName(layer.filter, layer.params)) return {};
    return name.toStdString();
}

}  // namespace

PaintView::PaintView(const StudioContext& context, QWidget* parent) : StageView(context, parent) {
    m_layers = new QListWidget(this);
    m_layers->setToolTip(
        tr("The filters chosen so far: select one to paint with it, double-click to rename it"));
    m_layers->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed);
    m_layers->setMaximumHeight(140);
    m_allowProgram = new QPushButton(tr("Allow its program…"), this);
    m_allowProgram->setObjectName(QStringLiteral("allowProgram"));
    m_allowProgram->setToolTip(
        tr("The selected layer runs a program you have not allowed: allow it, by its full path"));
    m_allowProgram->setVisible(false);
    auto* remove = new QPushButton(tr("Remove"), this);
    remove->setToolTip(tr("Remove the selected layer"));
    auto* everywhere = new QPushButton(tr("Everywhere"), this);
    everywhere->setToolTip(tr("Weight 1 everywhere for the selected layer"));
    auto* clear = new QPushButton(tr("Clear"), this);
    clear->setToolTip(tr("Weight 0 everywhere for the selected layer"));
    m_brushTool = new QToolButton(this);
    m_brushTool->setText(tr("Brush"));
    m_brushTool->setCheckable(true);
    m_brushTool->setChecked(true);
    m_brushTool->setToolTip(tr("Left button paints the layer in, right button paints it out (B)"));
    m_wandTool = new QToolButton(this);
    m_wandTool->setText(tr("Magic wand"));
    m_wandTool->setCheckable(true);
    m_wandTool->setToolTip(
        tr("Click: fill the connected area of similar features (left adds, "
           "right removes) (M)"));
    addToolButton(m_brushTool, ImageCanvas::Tool::Brush);
    addToolButton(m_wandTool, ImageCanvas::Tool::Wand);
    auto* diffuseButton = new QPushButton(tr("Diffuse"), this);
    diffuseButton->setToolTip(
        tr("Poisson diffusion: spread the painted weights smoothly over the "
           "unpainted pixels (D)"));
    m_size = new QDoubleSpinBox(this);
    m_size->setRange(1.0, 2048.0);
    m_size->setValue(48.0);
    m_size->setSuffix(tr(" px"));
    m_size->setToolTip(tr("Brush diameter ([ and ], or shift+drag on the image)"));
    m_softness = new QSlider(Qt::Horizontal, this);
    m_softness->setRange(0, 100);
    m_softness->setValue(50);
    m_softness->setToolTip(tr("Inner radius / outer radius: 1 is a hard brush"));
    m_wandTolerance = new QDoubleSpinBox(this);
    m_wandTolerance->setObjectName(QStringLiteral("wandTolerance"));
    m_wandTolerance->setRange(-1.0, 10.0);
    m_wandTolerance->setSingleStep(0.05);
    m_wandTolerance->setValue(denoise::WandOptions{}.color);
    m_wandTolerance->setToolTip(
        tr("How different a pixel's colour may be from the clicked one and still be selected, "
           "relative (larger selects more; −1: colour not used, features only)"));
    m_showWeight = new QCheckBox(tr("Show weight (O)"), this);
    m_showWeight->setObjectName(QStringLiteral("showWeight"));
    m_showWeight->setToolTip(
        tr("Where the selected layer shows: the rest of the image is dimmed (O)"));
    m_changeMap = new QCheckBox(tr("Show change map"), this);
    m_changeMap->setObjectName(QStringLiteral("changeMap"));
    m_changeMap->setToolTip(
        tr("Where the selected filter would change the current composite (a cyan and magenta "
           "checker, stronger where the change is larger)"));
    m_choiceMap = new QCheckBox(tr("Show choice map"), this);
    m_choiceMap->setObjectName(QStringLiteral("choiceMap"));
    m_choiceMap->setToolTip(
        tr("For Auto Start's result layer: which bank member auto chose at each pixel, coloured "
           "by member, with a legend"));
    m_side = new QLabel(this);
    m_side->setMinimumHeight(160);
    // The preview is scaled to the label: its pixmap must not widen the panel.
    m_side->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
    // Under its controls, not floating in the middle of a tall panel.
    m_side->setAlignment(Qt::AlignHCenter | Qt::AlignTop);
    m_side->setToolTip(tr("The selected filter applied everywhere"));
    m_state = new QLabel(this);
    m_state->setWordWrap(true);

    auto* layerButtons = new QHBoxLayout;
    layerButtons->addWidget(remove);
    layerButtons->addWidget(everywhere);
    layerButtons->addWidget(clear);
    auto* toolRow = new QHBoxLayout;
    toolRow->addWidget(m_brushTool);
    toolRow->addWidget(m_wandTool);
    toolRow->addWidget(diffuseButton);
    toolRow->addStretch(1);
    auto* form = new QFormLayout;
    form->addRow(tr("Size"), m_size);
    form->addRow(tr("Softness"), m_softness);
    form->addRow(tr("Wand tolerance"), m_wandTolerance);
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(new QLabel(tr("Layers (palette)"), this));
    layout->addWidget(m_layers);
    layout->addWidget(m_allowProgram);
    layout->addLayout(layerButtons);
    layout->addLayout(toolRow);
    layout->addLayout(form);
    // One a line: side by side they widened the panel past a 1366-px screen.
    layout->addWidget(m_showWeight);
    layout->addWidget(m_changeMap);
    layout->addWidget(m_choiceMap);
    layout->addWidget(m_side, 1);
    layout->addWidget(m_state);

    ImageCanvas* canvas = m_context.viewer->canvas();
    SessionAdapter* session = m_context.session;
    connect(m_layers, &QListWidget::currentRowChanged, this, &PaintView::layerSelected);
    connect(m_allowProgram, &QPushButton::clicked, this, [this] {
        if (!m_blockedProgram.isEmpty()) emit allowProgramRequested(m_blockedProgram);
    });
    // A name typed into a row: one undo step, saved with the session.
    // Applied after the editor has let go of the item: the list is rebuilt.
    connect(m_layers, &QListWidget::itemChanged, this, [this, session](QListWidgetItem* item) {
        const int row = m_layers->row(item);
        const QString text = item->text();
        QMetaObject::invokeMethod(
            this,
            [this, session, row, text] {
                if (!session->hasSession() || row < 0 ||
                    std::size_t(row) >= session->session().layerCount())
                    return;
                const denoise::SessionLayer& layer = session->session().layer(std::size_t(row));
                const std::string name = typedName(text, layer);
                if (name != layer.name)
                    session->renameLayer(std::size_t(row), name);
                else
                    rebuildLayers();  // the number and the name as they were
            },
            Qt::QueuedConnection);
    });
    connect(remove, &QPushButton::clicked, this, [this, session] {
        if (currentLayer() >= 0) session->removeLayer(std::size_t(currentLayer()));
    });
    connect(everywhere, &QPushButton::clicked, this, [this, session] {
        if (currentLayer() < 0) return;
        session->setWeights(
            std::size_t(currentLayer()),
            Image(session->session().width(), session->session().height(), 1, 1.0f));
    });
    connect(clear, &QPushButton::clicked, this, [this, session] {
        if (currentLayer() < 0) return;
        session->setWeights(
            std::size_t(currentLayer()),
            Image(session->session().width(), session->session().height(), 1, 0.0f));
    });
    connect(diffuseButton, &QPushButton::clicked, this, &PaintView::diffuse);
    connect(m_size, &QDoubleSpinBox::valueChanged, this,
            [this, canvas](double v) { canvas->setBrush(v, m_softness->value() / 100.0); });
    connect(m_softness, &QSlider::valueChanged, this,
            [this, canvas](int v) { canvas->setBrush(m_size->value(), v / 100.0); });
    connect(canvas, &ImageCanvas::brushResized, this, [this](double size) {
        m_size->blockSignals(true);
        m_size->setValue(size);
        m_size->blockSignals(false);
    });
    for (QCheckBox* box : {m_showWeight, m_changeMap, m_choiceMap})
        connect(box, &QCheckBox::toggled, this, [this, box](bool on) { overlayChosen(box, on); });
    // The wand's selection shows until the next stroke, click or layer.
    connect(session, &SessionAdapter::wandSelected, this,
            [this, canvas](std::shared_ptr<const Image> mask) {
                if (m_active && mask) canvas->setSelection(selectionOverlay(*mask));
            });

    // Strokes: a dab where the button went down, then dabs a quarter brush apart along the drag.
    connect(
        canvas, &ImageCanvas::strokeBegan, this, [this, session](const QPointF& at, bool subtract) {
            if (!m_active || currentLayer() < 0 || session->locked()) return;
            m_context.viewer->canvas()->setSelection(QImage());
            session->beginStroke(std::size_t(currentLayer()), brush(),
                                 subtract ? denoise::BrushMode::Subtract : denoise::BrushMode::Add);
            m_stroking = session->inStroke();
            if (!m_stroking) return;
            session->dab(at.x(), at.y());
            m_lastDab = at;
        });
    connect(canvas, &ImageCanvas::strokeMoved, this, &PaintView::strokeTo);
    connect(canvas, &ImageCanvas::strokeEnded, this, [this, session] {
        if (!m_stroking) return;
        m_stroking = false;
        m_lastDab.reset();
        session->endStroke();
    });
    connect(canvas, &ImageCanvas::wandClicked, this, &PaintView::wand);

    connect(session, &SessionAdapter::layersChanged, this, &PaintView::rebuildLayers);
    connect(session, &SessionAdapter::weightsChanged, this, &PaintView::updateOverlay);
    connect(session, &SessionAdapter::sessionReset, this, &PaintView::rebuildLayers);
    connect(session, &SessionAdapter::inputChanged, this, &PaintView::layerSelected);
    connect(m_context.viewer, &Viewer::channelChanged, this, &PaintView::layerSelected);
    // The side preview and the brush show the layer as the canvas does (exposure, mode).
    connect(canvas, &ImageCanvas::displayChanged, this, [this] {
        if (m_active) layerSelected();
    });
    connect(session, &SessionAdapter::compositeChanged, this, [this](const Rect&) {
        if (m_changeMap->isChecked() && !m_stroking) updateOverlay();
    });

    connect(session, &SessionAdapter::lockedChanged, this, [this](bool locked) {
        m_state->setText(locked ? tr("Diffusing or saving… painting waits.") : QString());
    });
}

int PaintView::currentLayer() const {
    if (!m_context.session->hasSession()) return -1;
    const int row = m_layers->currentRow();
    return row >= 0 && std::size_t(row) < m_context.session->session().layerCount() ? row : -1;
}

void PaintView::setCurrentLayer(int index) {
    m_layers->setCurrentRow(index);
}

denoise::Brush PaintView::brush() const {
    return denoise::Brush{m_size->value(), m_softness->value() / 100.0};
}

void PaintView::setBrushSize(double size) {
    m_size->setValue(size);
}

void PaintView::growBrush(double factor) {
    m_size->setValue(m_size->value() * factor);
}

void PaintView::rebuildLayers() {
    const int previous = m_layers->currentRow();
    const Image* previousData =
        currentLayer() >= 0
            ? m_context.session->session().layer(std::size_t(currentLayer())).output.get()
            : nullptr;
    const int before = m_layers->count();
    m_layers->blockSignals(true);
    m_layers->clear();
    if (m_context.session->hasSession()) {
        const denoise::Session& s = m_context.session->session();
        for (std::size_t i = 0; i < s.layerCount(); ++i) {
            m_layers->addItem(layerText(s.layer(i), i, m_context.session->autoChoice(i)));
            m_layers->item(int(i))->setFlags(m_layers->item(int(i))->flags() | Qt::ItemIsEditable);
            // The full parameters on the row; a layer that did not run says why.
            QListWidgetItem* item = m_layers->item(int(i));
            QString tip = layerParameters(s.layer(i).filter, s.layer(i).params);
            if (!s.layer(i).unavailable.empty()) {
                item->setText(tr("%1 (unavailable)").arg(item->text()));
                item->setForeground(palette().color(QPalette::Disabled, QPalette::Text));
                tip += QStringLiteral("\n\n") +
                       tr("Unavailable: %1").arg(QString::fromStdString(s.layer(i).unavailable));
            }
            item->setToolTip(tip);
        }
    }
    // A new layer becomes the one to paint with.
    int row = m_layers->count() > before ? m_layers->count() - 1 : previous;
    row = std::min(row, m_layers->count() - 1);
    m_layers->setCurrentRow(row);
    m_layers->blockSignals(false);
    // Converting a megapixel output for the brush and the side preview takes tens of ms: only
    // when the layer under the brush is another one.
    const int now = currentLayer();
    const Image* nowData =
        now >= 0 ? m_context.session->session().layer(std::size_t(now)).output.get() : nullptr;
    if (row != previous || nowData != previousData) {
        layerSelected();
    } else {
        updateAllowButton();
        updateOverlay();
    }
}

void PaintView::updateAllowButton() {
    m_blockedProgram.clear();
    const int layer = currentLayer();
    if (layer >= 0)
        for (const BlockedProgram& b : blockedPrograms(m_context.session->session()))
            if (std::find(b.layers.begin(), b.layers.end(), std::size_t(layer)) != b.layers.end())
                m_blockedProgram = b.program;
    m_allowProgram->setVisible(!m_blockedProgram.isEmpty());
}

void PaintView::layerSelected() {
    const int layer = currentLayer();
    ImageCanvas* canvas = m_context.viewer->canvas();
    if (m_active) canvas->setSelection(QImage());
    updateAllowButton();
    updateOverlay();
    if (layer < 0) {
        m_tasks.cancel(QStringLiteral("convert"));
        if (m_active) canvas->setBrushSource(nullptr);
        updateSidePreview();
        return;
    }
    // The layer's output converted for the brush and the side preview on a worker: a megapixel
    // takes tens of milliseconds.
    struct Converted {
        Image output;
        QImage full, side;
    };
    // Shared, not copied: layer outputs are immutable.
    std::shared_ptr<const Image> output =
        m_context.session->session().layer(std::size_t(layer)).output;
    const DisplaySettings display = canvas->display();
    const int side = std::max(160, m_side->width() - 8);
    const bool underBrush = m_context.viewer->channel() == Viewer::Channel::Result;
    m_tasks.run<Converted>(
        QStringLiteral("convert"),
        [output, display, side](const TaskRunner::CancelFlag&) {
            Converted c{*output, toQImage(*output, display), {}};
            c.side = c.full.scaled(side, side, Qt::KeepAspectRatio, Qt::SmoothTransformation);
            return c;
        },
        [this, underBrush](Converted c) {
            // What the brush would paint shows under it when the canvas shows the result.
            if (m_active && underBrush)
                m_context.viewer->canvas()->setBrushSource(std::move(c.output), std::move(c.full));
            else if (m_active)
                m_context.viewer->canvas()->setBrushSource(nullptr);
            m_side->setText(QString());
            m_side->setPixmap(QPixmap::fromImage(c.side));
        });
}

void PaintView::updateSidePreview() {
    if (currentLayer() >= 0) return;  // layerSelected converts it
    m_side->setPixmap(QPixmap());
    m_side->setText(tr("Choose a filter in stage 3 to paint with it."));
}

void PaintView::overlayChosen(QCheckBox* box, bool on) {
    if (on)
        for (QCheckBox* other : {m_showWeight, m_changeMap, m_choiceMap})
            if (other != box) {
                const QSignalBlocker block(other);
                other->setChecked(false);
            }
    updateOverlay();
}

void PaintView::toggleWeightOverlay() {
    m_showWeight->toggle();
}

void PaintView::updateOverlay() {
    ImageCanvas* canvas = m_context.viewer->canvas();
    const int layer = currentLayer();
    const SessionAdapter::AutoChoiceMap* choice =
        layer >= 0 ? m_context.session->autoChoice(std::size_t(layer)) : nullptr;
    m_choiceMap->setEnabled(choice != nullptr);
    const bool any = m_showWeight->isChecked() || m_changeMap->isChecked() ||
                     (m_choiceMap->isChecked() && choice);
    if (!m_active || !any || layer < 0) {
        m_tasks.cancel(QStringLiteral("change"));
        canvas->clearOverlay();
        return;
    }
    // The maps on a worker, from copies (the composite and weights change under the brush).
    const denoise::Session& s = m_context.session->session();
    if (m_showWeight->isChecked()) {
        auto weights = std::make_shared<const Image>(s.layer(std::size_t(layer)).weights);
        m_tasks.run<ChoiceOverlay>(
            QStringLiteral("change"),
            [weights](const TaskRunner::CancelFlag&) {
                return ChoiceOverlay{weightOverlay(*weights), {}};
            },
            [this](ChoiceOverlay overlay) { showOverlay(overlay.image, overlay.legend); });
        return;
    }
    if (m_choiceMap->isChecked()) {
        const SessionAdapter::AutoChoiceMap map = *choice;
        m_tasks.run<ChoiceOverlay>(
            QStringLiteral("change"),
            [map](const TaskRunner::CancelFlag&) { return choiceOverlay(map); },
            [this](ChoiceOverlay overlay) { showOverlay(overlay.image, overlay.legend); });
        return;
    }
    std::shared_ptr<const Image> output = s.layer(std::size_t(layer)).output;
    auto composite = std::make_shared<const Image>(s.composite());
    m_tasks.run<ChoiceOverlay>(
        QStringLiteral("change"),
        [output, composite](const TaskRunner::CancelFlag&) {
            // The square root lifts the small changes a bright edge would otherwise hide (the
            // map is divided by its largest value).
            Image change = denoise::changeMap(*output, *composite);
            for (float& v : change.data()) v = std::sqrt(v);
            return ChoiceOverlay{changeOverlay(change), {}};
        },
        [this](ChoiceOverlay overlay) { showOverlay(overlay.image, overlay.legend); });
}

void PaintView::showOverlay(const QImage& image, const QList<QPair<QColor, QString>>& legend) {
    if (!m_active || currentLayer() < 0) return;
    ImageCanvas* canvas = m_context.viewer->canvas();
    canvas->setOverlay(image);
    canvas->setLegend(legend);
}

void PaintView::strokeTo(const QPointF& at) {
    if (!m_stroking || !m_lastDab) return;
    // Dabs a quarter of the brush apart (at least one pixel), so a fast drag leaves no gaps.
    const double spacing = std::max(1.0, 0.25 * m_size->value());
    const QPointF d = at - *m_lastDab;
    const double length = std::hypot(d.x(), d.y());
    if (length < spacing) return;
    const int steps = int(length / spacing);
    for (int k = 1; k <= steps; ++k) {
        const QPointF p = *m_lastDab + d * (double(k) * spacing / length);
        m_context.session->dab(p.x(), p.y());
    }
    m_lastDab = *m_lastDab + d * (double(steps) * spacing / length);
}

void PaintView::wand(const QPoint& pixel, bool subtract) {
    const int layer = currentLayer();
    if (!m_active || layer < 0 || !m_context.session->filterInput() || m_context.session->locked())
        return;
    denoise::WandOptions options;
    options.color = m_wandTolerance->value();
    m_context.session->wand(std::size_t(layer), pixel.x(), pixel.y(), options,
                            subtract ? denoise::BrushMode::Subtract : denoise::BrushMode::Add);
}

void PaintView::diffuse() {
    if (!m_context.session->hasSession()) return;
    const denoise::Session& s = m_context.session->session();
    std::vector<std::size_t> layers;
    for (std::size_t i = 0; i < s.layerCount(); ++i) {
        bool painted = false;
        for (float v : s.layer(i).painted.data())
            if (v > 0.0f) {
                painted = true;
                break;
            }
        if (painted) layers.push_back(i);
    }
    if (layers.empty()) {
        m_state->setText(tr("Paint a few strokes first: diffusion spreads them."));
        return;
    }
    m_context.session->diffuse(layers);
}

void PaintView::activate() {
    ImageCanvas* canvas = m_context.viewer->canvas();
    applyTool();
    canvas->setBrush(m_size->value(), m_softness->value() / 100.0);
    layerSelected();
}

void PaintView::deactivate() {
    ImageCanvas* canvas = m_context.viewer->canvas();
    canvas->setBrushSource(nullptr);
    canvas->clearOverlay();
    canvas->setSelection(QImage());
}

}  // namespace glint::studio
