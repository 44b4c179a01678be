#include "drape/drape.hpp"

int odr_b_node_count() { return drape::Clothd{drape::ClothSpecd{}}.node_count(); }
