// Debug lines (silhouette edges, wedge hulls): one colour, alpha for blending.
layout(location = 2) uniform vec4 uColour;

layout(location = 0) out vec4 oColor;

void main() {
    oColor = uColour;
}
