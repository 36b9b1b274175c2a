// The viewer: the image canvas with tev's viewing controls — channel, exposure, offset,
// sRGB/linear/false colour, fit and 1:1, A/B flip and wipe against the reference, error images —
// and the pixel read-out of every layer under the cursor.
#pragma once

#include <QWidget>

#include <optional>

#include "glint/image/image.h"
#include "model/document.h"
#include "model/session_adapter.h"
#include "views/image_canvas.h"

class QComboBox;
class QDoubleSpinBox;
class QSlider;
class QToolButton;
class QCheckBox;

namespace glint::studio {

class Viewer : public QWidget {
    Q_OBJECT
  public:
    /// What the canvas shows.
    enum class Channel {
        Result,  ///< the composite (the render while it refines, or without a session)
        Render,  ///< the render's colour, unfiltered
        Albedo,
        Normal,
        Depth,  ///< histogram-equalised
        ColorVariance,
        AlbedoVariance,
        NormalVariance,
        DepthVariance,
        SampleCount,
        Reference,
        ErrorAbsolute,  ///< |result − reference|
        ErrorSquared,   ///< (result − reference)²
        ErrorRelative   ///< |result − reference| / (reference + 0.01)
    };

    Viewer(Document* document, SessionAdapter* session, QWidget* parent = nullptr);

    ImageCanvas* canvas() { return m_canvas; }
    Channel channel() const { return m_channel; }
    void setChannel(Channel channel);
    /// The image the Result channel shows now (composite, or the render).
    const Image* resultImage() const;
    /// Redraws from the model.
    void refresh();
    /// While held, redraws wait; releasing redraws once if any waited (a restore changes the
    /// file, the session and the render at once: one redraw, not three).
    void holdRedraws(bool held);
    /// Shows the reference instead of the result while `on` (the A/B flip key).
    void setFlipped(bool on);
    void toggleFlip();
    /// The wipe: the result left of a line the user drags on the canvas, the reference right.
    void setWipe(bool on);
    void toggleWipe();
    bool wipe() const;
    /// What the canvas says it shows ("Result (denoised, 16 spp)", "B: Reference (4096 spp)",
    /// "Wipe: result | reference"...), drawn in its corner.
    QString label() const { return m_canvas->label(); }
    /// False colour maps the 1st–99th percentiles of the shown values (on by default) or [0, 1].
    void setAutoRange(bool on);
    void setExposure(double stops);
    double exposure() const;
    void setDisplayMode(DisplayMode mode);
    /// The read-out of the pixel under the cursor (empty outside the image).
    QString readout() const { return m_readout; }

  signals:
    void readoutChanged(const QString& text);
    void channelChanged(glint::studio::Viewer::Channel channel);
    void exposureChanged(double stops);

  private:
    void onCompositeChanged(const Rect& rect);
    void updateReadout(int x, int y);
    void applyDisplay();
    bool showingComposite() const;
    bool keepsDenoised() const;
    void updateLabel();
    void updateCompare();
    /// The channel box's minimum width: its current item whole (at most its widest item's).
    void fitChannelBox();

    Document* m_document;
    SessionAdapter* m_session;
    ImageCanvas* m_canvas;
    QComboBox* m_channelBox;
    QDoubleSpinBox* m_exposure;
    QDoubleSpinBox* m_offset;
    QComboBox* m_mode;
    QToolButton* m_flip;
    QCheckBox* m_wipeBox;
    QSlider* m_wipe;
    QToolButton* m_autoRange;
    Channel m_channel = Channel::Result;
    bool m_held = false, m_redrawWaits = false;
    Image m_shown;             // the linear image on the canvas when it is not the composite itself
    float m_statScale = 0.0f;  // what a statistics channel was divided by for display (0: none)
    QString m_readout;
    int m_hoverX = -1, m_hoverY = -1;
};

/// Whether `channel` is a statistic (a variance, the sample count): shown normalised.
bool isStatistic(Viewer::Channel channel);
/// The name of a viewer channel, for menus.
QString channelName(Viewer::Channel channel);
/// A viewer channel's name in session files and the journal ("result", "albedo", "sampleCount",
/// …): never translated, never changed once written.
QString channelKey(Viewer::Channel channel);
/// The channel a session file or journal line names; none for a name no channel has.
std::optional<Viewer::Channel> channelFromKey(const QString& key);

}  // namespace glint::studio
