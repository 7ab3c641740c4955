#include "render/image/image.hpp"
