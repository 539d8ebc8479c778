"""jointwear.report"""
