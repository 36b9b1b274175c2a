#include "glint/image/io.h"
