// Renders a green box headless through an installed sgfx and checks the centre pixel.
#include "GreenBox.h"

int main() {
    auto viewer = greenBoxViewer();
    return drawsGreen(*viewer, "consumer") ? 0 : 1;
}
